// Sample: emitter intensities from the photo (section 3.4, without a network).
//
//   ps_sample_light [SCENE.json]
//
// Each part gets a neutral material guess (its median photo color as albedo, roughness 0.7),
// the path tracer renders every light alone at unit radiance, and a non-negative least-squares
// fit finds the RGB radiance of each light that best explains the photo's pixels.
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "photoscene/align.hpp"
#include "photoscene/core.hpp"
#include "photoscene/lighting.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/scene.hpp"

int main(int argc, char** argv) {
  ps::initLogging(ps::LogLevel::Warn);
  const std::string scenePath = argc > 1 ? argv[1] : PS_SAMPLE_SCENE;
  try {
    ps::Scene scene = ps::loadScene(scenePath);
    const ps::View& view = scene.views[0];
    // neutral materials: the median photo color of each labelled part
    std::vector<ps::PartMaterial> materials;
    for (const ps::Part& p : scene.parts) materials.push_back(ps::PartMaterial::defaultGray(p.name));
    for (const auto& [label, part] : view.segmentParts) {
      const cv::Mat mask = view.segments == label;
      if (cv::countNonZero(mask) == 0) continue;
      const cv::Vec3f median = ps::align::maskedMedian(view.photo, mask);
      materials[part].albedo = ps::Vec3f(median[0], median[1], median[2]).cwiseMin(1.0f);
      materials[part].roughness = 0.7f;
    }
    const ps::PathTracer tracer(scene, materials);
    const ps::Camera camera = view.camera.resized(view.camera.width() / 2, view.camera.height() / 2);
    ps::RenderOptions options;
    options.spp = 16;
    const std::vector<cv::Mat> perLight = tracer.renderPerLight(camera, options);
    ps::lighting::ViewLightData data;
    cv::resize(view.photo, data.photo, camera.width() == view.photo.cols ? view.photo.size()
                                                                          : cv::Size(camera.width(), camera.height()),
               0, 0, cv::INTER_AREA);
    cv::Mat labelled;
    cv::resize(view.segments > 0, labelled, data.photo.size(), 0, 0, cv::INTER_NEAREST);
    data.mask = labelled;
    data.perLight = perLight;
    const ps::lighting::LightSolution s = ps::lighting::solveLights({data});
    const auto lights = scene.lights.all();  // the order of renderPerLight
    for (size_t k = 0; k < lights.size(); ++k)
      std::printf("%-12s radiance (%.2f, %.2f, %.2f)%s\n", lights[k]->label().c_str(),
                  s.intensity[k].x(), s.intensity[k].y(), s.intensity[k].z(),
                  s.dropped[k] ? " (dropped)" : "");
    std::printf("residual rms %.4f of photo rms %.4f\n", s.residualRms, s.photoRms);
    return 0;
  } catch (const ps::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
