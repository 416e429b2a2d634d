// The incident-light grid: at every `stride`-th image pixel, the radiance arriving over the
// hemisphere of the visible surface point, traced through the scene with its current materials
// and lights; what the differentiable render layer shades with.
//
// Representation (chosen by measurement, see modules/raytrace/README.md): a thetaBins x phiBins
// grid over the hemisphere of the local shading frame (as the paper's 8 x 16), bins of EQUAL
// SOLID ANGLE: bin (i, j) spans cos(theta) in [1 - (i + 1) / thetaBins, 1 - i / thetaBins] and
// phi in [2 pi j / phiBins, 2 pi (j + 1) / phiBins); the value is the mean incident radiance over
// the bin (W m^-2 sr^-1, linear RGB). Frame: N = interpolated shading normal facing the camera,
// T = unit dP/du orthogonalised (the OBJ uv tangent; an arbitrary tangent where uvs degenerate),
// B = N x T. Directions point AWAY from the surface (towards where the light comes from).
//
//   ps::IncidentLightGrid grid = ps::computeIncidentLight(tracer, gbuffer, camera, {});
//   ps::Vec3f Lo = grid.shade(gx, gy, bsdf, woLocal);   // sum_bins L f cos dOmega
#pragma once

#include <vector>

#include "photoscene/raytrace/gbuffer.hpp"
#include "photoscene/raytrace/path_tracer.hpp"

namespace ps {

struct IncidentLightOptions {
  int stride =
      8;  ///< grid point every `stride` pixels (at pixel centers stride/2 + k stride... see below)
  int thetaBins = 8;
  int phiBins = 16;
  int samplesPerBin =
      4;  ///< stratified path samples per bin (each one path-traced radiance estimate)
  /// Light samples per light at every grid point (0: none). The light that reaches a point
  /// straight from an emitter is then estimated twice, by the bins' path samples and by
  /// sampling the emitters (PathTracer::sampleDirectLight), and the two are combined by
  /// multiple importance sampling (power heuristic). With path samples alone a small lamp is
  /// found by a few of a bin's samples or none, and the grid's shading varies by tens of percent
  /// from point to point: blotches that the fit reads as texture (modules/raytrace/README.md).
  int directSamples = 32;
  RenderOptions render;  ///< lights, bounce limits, seed (spp and filter are not used)
  /// Which parts need grid points, by part id (empty: all). A point whose pixel sees another
  /// part is not traced and stays invalid; the others are the same as without the list (each
  /// point draws from its own random stream).
  std::vector<uint8_t> parts;
  /// Also record, per grid point, what its irradiance owes to each part's diffuse albedo
  /// (IncidentLightGrid::albedoSensitivity): what a fit needs to correct for light that its
  /// own albedos bounce back onto it.
  bool albedoSensitivity = false;
};

struct IncidentLightGrid {
  int width = 0,
      height = 0;  ///< grid size: ceil(image width / stride) x ceil(image height / stride)
  int stride = 1;
  int thetaBins = 8, phiBins = 16;
  /// Grid point (gx, gy) sits at pixel (gx * stride + stride / 2, gy * stride + stride / 2)
  /// (clamped into the image).
  std::vector<Vec3f> radiance;  ///< [((gy * width + gx) * thetaBins + i) * phiBins + j]
  std::vector<uint8_t> valid;   ///< per grid point: 1 where the pixel sees a surface
  std::vector<Vec3f> position, frameT, frameB, frameN;  ///< per grid point, world space
  /// With IncidentLightOptions::albedoSensitivity: per grid point, per part, d E / d ln a_part,
  /// E the point's irradiance (sum over bins of L cos dOmega, linear RGB) and a_part the scale
  /// of the part's diffuse albedo (AlbedoSensitivity), in compressed rows: point k's entries
  /// are [sensitivityStart[k], sensitivityStart[k + 1]) of sensitivityPart / sensitivityValue.
  /// Empty without the option.
  std::vector<int> sensitivityStart, sensitivityPart;
  std::vector<Vec3f> sensitivityValue;

  int pixelX(int gx, int imageWidth) const;
  int pixelY(int gy, int imageHeight) const;
  const Vec3f& at(int gx, int gy, int i, int j) const {
    return radiance[((static_cast<size_t>(gy) * width + gx) * thetaBins + i) * phiBins + j];
  }
  /// Local direction (z = N) of the center of bin (i, j) (in cos theta and phi).
  Vec3f binDirection(int i, int j) const;
  /// Solid angle of every bin: 2 pi / (thetaBins * phiBins).
  float binSolidAngle() const { return 2 * kPi / (thetaBins * phiBins); }
  /// Reflected radiance toward local direction woLocal: sum over bins of L f(wo, d) cos dOmega,
  /// with each bin's BRDF and cosine averaged over `sub` x `sub` sub-directions (sub >= 1).
  Vec3f shade(int gx, int gy, const MicrofacetBsdf& bsdf, const Vec3f& woLocal, int sub = 2) const;
  /// Irradiance at grid point (gx, gy): sum over bins of L cos(bin centre) dOmega.
  Vec3f irradiance(int gx, int gy) const;
};

/// Traces the grid for `camera` (the size of `gbuffer`, which must come from the same camera).
IncidentLightGrid computeIncidentLight(const PathTracer& tracer, const GBuffer& gbuffer,
                                       const Camera& camera,
                                       const IncidentLightOptions& options = {});

/// A real spherical-harmonics fit of incident radiance (order `bands` - 1, bands^2 coefficients
/// per channel) over the local hemisphere, for comparing representations.
struct ShRadiance {
  int bands = 3;
  std::vector<Vec3f> coeffs;
  Vec3f eval(const Vec3f& dirLocal) const;
};
/// Projects a grid point's bins onto SH (the lower hemisphere is set to 0).
ShRadiance projectToSh(const IncidentLightGrid& grid, int gx, int gy, int bands);
/// Real SH basis values Y_lm(dir) for l < bands, ordered l^2 + l + m.
void shBasis(const Vec3f& dir, int bands, float* out);

}  // namespace ps
