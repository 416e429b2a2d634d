#include "photoscene/raytrace/render_twin.hpp"

#include "photoscene/core/log.hpp"

#include <algorithm>

#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/raytrace/denoise.hpp"
#include "photoscene/io/image_io.hpp"

namespace ps {

namespace fs = std::filesystem;

cv::Mat renderTwinView(const PathTracer& tracer, const Camera& camera, const RenderOptions& options,
                       double exposure, RenderStats* stats, bool denoise) {
  DenoiseGuides guides;
  cv::Mat img = tracer.render(camera, options, stats, denoise ? &guides : nullptr);
  if (denoise) {
    Timer t;
    img = ps::denoise(guides, img);
    spdlog::debug("denoised {}x{} in {:.2f} s", img.cols, img.rows, t.seconds());
  }
  if (exposure != 1.0) img *= exposure;
  return img;
}

std::vector<fs::path> renderTwinCommand(const TwinRenderRequest& req) {
  std::string ext = req.output.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".png" && ext != ".exr" && ext != ".hdr" && ext != ".jpg" && ext != ".jpeg")
    throw InputError(req.output.string(), "-o", "an image path ending in .png, .exr, .hdr or .jpg");
  if (req.output.has_parent_path() && !fs::is_directory(req.output.parent_path()))
    throw InputError(req.output.string(), "-o", "an existing folder for the output image");
  std::string err;
  if (!req.options.IsValid(&err)) throw InputError("command line", "render options", err);
  if (req.width < 0 || req.height < 0 || (req.width > 0) != (req.height > 0))
    throw InputError("command line", "--width/--height", "both positive, or neither");
  if (!fs::is_directory(req.twinDir))
    throw InputError(req.twinDir.string(), "", "a twin output folder (with scene.json, lights.json, materials/)");

  Twin twin = loadTwin(req.twinDir);
  std::vector<double> exposure = twin.exposure;
  std::string lightsSource = (req.twinDir / "lights.json").string();
  if (!fs::exists(lightsSource)) lightsSource = (req.twinDir / "scene.json").string();
  if (req.lightsFile) {
    if (!fs::exists(*req.lightsFile)) throw InputError(req.lightsFile->string(), "", "an existing lights.json");
    const io::LightsFileDesc ld = io::readLightsJson(*req.lightsFile);
    twin.scene.lights = makeLights(ld, twin.scene.mesh, twin.scene.parts, twin.scene.up, req.lightsFile->string());
    lightsSource = req.lightsFile->string();
    if (!ld.exposure.empty()) {
      exposure = ld.exposure;
      exposure.resize(twin.scene.views.size(), 1.0);
    }
  }
  const auto lights = twin.scene.lights.all();
  for (size_t i = 0; i < lights.size(); ++i)
    if (!lights[i]->scale())
      throw InputError(lightsSource, "emitters[" + std::to_string(i) + "].radiance",
                       "a radiance for emitter '" + lights[i]->label() +
                           "' (fitted intensities are needed to render)");
  if (lights.empty())
    throw InputError(lightsSource, "emitters", "at least one emitter or an environment");

  std::vector<std::pair<Camera, double>> views;  // camera, exposure
  std::vector<fs::path> outputs;
  if (req.cameraFile) {
    if (!fs::exists(*req.cameraFile)) throw InputError(req.cameraFile->string(), "", "an existing CAMERA.json");
    views.emplace_back(Camera::fromDesc(io::readCameraJson(*req.cameraFile)), 1.0);
    outputs.push_back(req.output);
  } else {
    if (twin.scene.views.empty()) throw InputError((req.twinDir / "scene.json").string(), "views", "at least one view, or --camera");
    for (size_t i = 0; i < twin.scene.views.size(); ++i) {
      views.emplace_back(twin.scene.views[i].camera, i < exposure.size() ? exposure[i] : 1.0);
      if (twin.scene.views.size() == 1) outputs.push_back(req.output);
      else
        outputs.push_back(req.output.parent_path() /
                          (req.output.stem().string() + "_view" + std::to_string(i) + req.output.extension().string()));
    }
  }
  const PathTracer tracer(twin.scene, twin.materials);
  std::vector<cv::Mat> images;
  for (size_t i = 0; i < views.size(); ++i) {
    Camera cam = views[i].first;
    if (req.width > 0) cam = cam.resized(req.width, req.height);
    RenderStats stats;
    images.push_back(renderTwinView(tracer, cam, req.options, views[i].second, &stats, req.denoise));
    spdlog::info("render {}: {}x{} at {} spp in {:.2f}s ({:.2f} Mrays/s)", outputs[i].string(), cam.width(),
                 cam.height(), req.options.spp, stats.seconds, stats.raysPerSecond() * 1e-6);
    PS_Check(allFinite(images.back()), "non-finite pixels in the render");
  }
  for (size_t i = 0; i < images.size(); ++i) {
    io::WriteOptions wo;
    if (ext == ".exr") wo.bits = 32;
    io::writeImage(outputs[i], images[i], wo);
  }
  return outputs;
}

}  // namespace ps
