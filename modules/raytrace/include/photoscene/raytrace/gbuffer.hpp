// Geometry buffers of one view at any resolution: what every later stage reads per pixel.
//
// All per-pixel values are taken from the ray through the pixel CENTER (OpenCV convention:
// pixel (x, y) is centered at (x, y)); the per-part coverage M_geo averages an n x n stratified
// grid of sub-pixel rays over the pixel's box [x - 0.5, x + 0.5] x [y - 0.5, y + 0.5].
// Normals and tangents are world-space unit vectors flipped to face the camera.
//
//   ps::GBuffer gb = ps::renderGBuffer(tracer, camera.resized(320, 240));
//   int part = gb.partId.at<int>(y, x);            // -1: background
//   cv::Mat mask = gb.mask[part];                   // CV_8UC1, 255 where the center ray hits part
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/raytrace/path_tracer.hpp"
#include "photoscene/scene/camera.hpp"

namespace ps {

struct GBuffer {
  cv::Mat partId;         ///< CV_32SC1, part id of the first hit, -1 where the ray escapes
  cv::Mat triangleId;     ///< CV_32SC1, mesh triangle, -1 where the ray escapes
  cv::Mat uv;             ///< CV_32FC2, OBJ texture coordinates (v up); 0 where no hit
  cv::Mat duvdx, duvdy;   ///< CV_32FC2, d(uv)/d(pixel x), d(uv)/d(pixel y) (ray differentials on the hit plane)
  cv::Mat position;       ///< CV_32FC3, world position (m)
  cv::Mat normalGeo;      ///< CV_32FC3, unit geometric normal, facing the camera
  cv::Mat normalShading;  ///< CV_32FC3, unit interpolated (per-corner) normal, facing the camera
  cv::Mat tangent;        ///< CV_32FC3, unit dP/du orthogonalised against normalShading (0 if degenerate)
  cv::Mat bitangent;      ///< CV_32FC3, unit, normalShading x tangent, signed like dP/dv
  cv::Mat dpdu, dpdv;     ///< CV_32FC3, dP/du and dP/dv of the hit triangle (m per uv unit); the
                          ///< render layer builds the frame of t = M uv + o from these (ps::tangentFrame)
  cv::Mat depth;          ///< CV_32FC1, camera-space z (m), 0 where no hit
  std::vector<cv::Mat> coverage;  ///< per part: CV_32FC1 in [0, 1], anti-aliased M_geo (empty Mat if never hit)
  std::vector<cv::Mat> mask;      ///< per part: CV_8UC1, 255 where partId == part (empty Mat if never hit)
};

struct GBufferOptions {
  int coverageSamples = 4;  ///< n: n x n sub-pixel rays per pixel for the coverage (1: center only)
  bool passWindows = false; ///< true: window parts are transparent (report what lies behind them)
};

/// Renders the G-buffers of `camera` (its width x height).
GBuffer renderGBuffer(const PathTracer& tracer, const Camera& camera, const GBufferOptions& options = {});

}  // namespace ps
