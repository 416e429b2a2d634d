// A lit preview of material maps: a sphere (or a flat plane) shaded with Lambert diffuse + GGX
// specular (alpha = roughness^2, separable Smith masking, Schlick Fresnel with
// F0 = lerp(0.04, albedo, metallic): core/shading.hpp's terms, as the path tracer and the render
// layer) under one key light and a soft ambient term.
#pragma once

#include "photoscene/graph/material_graph.hpp"

namespace ps {

enum class PreviewShape { Sphere, Plane };

struct PreviewOptions {
  int size = 256;                      ///< output image size (square)
  PreviewShape shape = PreviewShape::Sphere;
  float uvRepeat = 2.f;                ///< texture repeats across the sphere's front / the plane
  cv::Vec3f background{0.02f, 0.02f, 0.025f};  ///< linear RGB
};

/// Renders `maps` (albedo, normal, roughness required; metallic optional; see
/// material_graph.hpp for their conventions).
/// @return CV_32FC3, linear RGB (R first), size options.size, values >= 0 (may exceed 1 on
///         highlights; encode with ps::linearToSrgb for display)
cv::Mat renderMaterialPreview(const MaterialMaps& maps, const PreviewOptions& options = {});

}  // namespace ps
