// `photoscene render`: draws a twin output folder (../shared/spec/scene-format.md section 4)
// from its input views or a given camera, optionally relit by a lights.json.
//
//   ps::TwinRenderRequest req;
//   req.twinDir = "OUT";  req.output = "v0.exr";  req.options.spp = 128;
//   ps::renderTwinCommand(req);      // writes v0.exr (one view) or v0_view<i>.exr (several)
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "photoscene/raytrace/path_tracer.hpp"
#include "photoscene/scene/material.hpp"

namespace ps {

struct TwinRenderRequest {
  std::filesystem::path twinDir;                    ///< OUT (scene.json, lights.json, materials/, textures/)
  std::optional<std::filesystem::path> cameraFile;  ///< CAMERA.json: one camera object; else every input view
  std::optional<std::filesystem::path> lightsFile;  ///< LIGHTS.json: relight (replaces emitters and environment)
  std::filesystem::path output;                     ///< IMAGE.{png,exr,hdr,jpg}
  RenderOptions options;
  bool denoise = false;       ///< ps::denoise the render (renderTwinView)
  int width = 0, height = 0;  ///< 0: the camera's size; else the camera resized (same field of view)
};

/// Renders one view of a loaded twin: the path-traced image times `exposure` (CV_32FC3 linear).
/// `denoise`: filtered by ps::denoise, guided by the render's own first-hit albedo, normal,
/// depth and per-pixel variance (for images people look at and the evaluation's renders; never
/// for what the light solve or the fit read).
cv::Mat renderTwinView(const PathTracer& tracer, const Camera& camera, const RenderOptions& options,
                       double exposure = 1.0, RenderStats* stats = nullptr, bool denoise = false);

/// Checks the request, loads the twin, renders and writes the image(s) atomically; nothing is
/// written unless every view rendered. Several input views (no camera file) are written as
/// <stem>_view<i><ext>. Input views are multiplied by lights.json's exposure[i]; a --camera
/// render is not. Throws ps::InputError for bad input (a missing folder or file, an output
/// extension other than png / exr / hdr / jpg, an emitter without radiance).
/// Returns the files written.
std::vector<std::filesystem::path> renderTwinCommand(const TwinRenderRequest& request);

}  // namespace ps
