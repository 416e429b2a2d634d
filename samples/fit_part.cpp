// Sample: fitting one part's material graph to the photo (paper sections 3.3-3.4).
//
//   ps_sample_fit_part [SCENE.json] [LIGHTS.json] [PART] [GRAPH] [OUT.png]
//
// The lights come from a lights.json (default: the sample's true lights, so this program shows
// the fit alone; `photoscene run` recovers them from the photo). The geometry buffers and the
// incident-light grid of view 0 are computed once with gray materials; then the graph's
// parameters, one mean roughness and the UV transform are fitted so that the render layer's image
// of the part matches the photo's statistics and texture. Writes photo | fitted render.
#include <cstdio>

#include "photoscene/core.hpp"
#include "photoscene/graph.hpp"
#include "photoscene/io.hpp"
#include "photoscene/optim.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/scene.hpp"

int main(int argc, char** argv) {
  ps::initLogging(ps::LogLevel::Warn);
  const std::string scenePath = argc > 1 ? argv[1] : PS_SAMPLE_SCENE;
  const std::string lightsPath = argc > 2 ? argv[2] : PS_SAMPLE_TWIN "/lights.json";
  const std::string partName = argc > 3 ? argv[3] : "floor";
  const std::string graphName = argc > 4 ? argv[4] : "wood_planks";
  const std::string outPath = argc > 5 ? argv[5] : "sample-fit.png";
  try {
    ps::Scene scene = ps::loadScene(scenePath);
    const ps::io::LightsFileDesc lights = ps::io::readLightsJson(lightsPath);
    scene.lights = ps::makeLights(lights, scene.mesh, scene.parts, scene.up, lightsPath);
    const int part = scene.partId(partName);
    if (part < 0) throw ps::InputError(scenePath, "", "a part named '" + partName + "'");
    const ps::View& view = scene.views[0];

    // once per view: geometry buffers and incident light (gray materials stand in for the rest)
    const std::vector<ps::PartMaterial> gray;
    const ps::PathTracer tracer(scene, gray);
    const ps::GBuffer gb = ps::renderGBuffer(tracer, view.camera);
    const ps::IncidentLightGrid grid = ps::computeIncidentLight(tracer, gb, view.camera);
    if (gb.mask[part].empty()) throw ps::InputError(scenePath, "", "part '" + partName + "' seen in view 0");

    // the part's pixels: where the geometry shows it and the photo's label agrees
    cv::Mat mask = gb.mask[part].clone();
    for (const auto& [label, p] : view.segmentParts)
      if (p == part) mask &= (view.segments == label);
    const ps::PartGeometry geo =
        ps::preparePartGeometry(gb, view.camera.position().cast<float>(), grid, mask, part);

    const ps::GraphLibrary library = ps::GraphLibrary::load();
    const ps::TextureLossTarget target(view.photo, mask);
    ps::PartFitOptions options = ps::PartFitOptions::preset("fast");
    options.onProgress = [](const ps::PartFitProgress& p) {  // progress; returning false stops
      if (p.phase == ps::PartFitProgress::Phase::Step && p.iteration % 20 == 0)
        std::printf("  step %d: loss %.4f\n", p.iteration, p.loss);
      return true;
    };
    const ps::PartFitResult r = ps::fitPart(library.get(graphName), geo, view.photo, target, options);

    std::printf("%s with %s: %d pixels, loss %.4f -> %.4f in %d iterations (%.1f s)\n", partName.c_str(),
                graphName.c_str(), geo.size(), r.initialLoss, r.loss, r.iterations, r.seconds);
    const ps::UvTransform uv = r.uv.toTransform();
    std::printf("UV rotation %.1f deg, scale %.3f, offset (%.3f, %.3f); roughness %.3f\n", uv.rotationDeg,
                uv.scale.x(), uv.offset.x(), uv.offset.y(), r.roughness);
    cv::Mat photoPart = cv::Mat::zeros(view.photo.size(), CV_32FC3);
    view.photo.copyTo(photoPart, mask);
    cv::Mat side;
    cv::hconcat(photoPart, r.render, side);
    ps::io::writeImage(outPath, side);
    std::printf("wrote %s (photo | fitted render)\n", outPath.c_str());
    return 0;
  } catch (const ps::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
