// The differentiable per-part render layer (paper section 3.3, Eq. 2-5): from texture-space
// material maps and a UV transform to the image of one part as the camera sees it, shaded by the
// incident-light grid, with its exact reverse-mode gradient.
//
// Per masked pixel p (all quantities in the pixel's local shading frame T, B, N of the G-buffer):
//   t      = R(rotation) * (exp(logScale) * uv_p) + offset                 (spec section 3)
//   lod    = log2(max(|duv/dx|, |duv/dy|) * exp(logScale) * mapSize)        (pixel footprint)
//   A, n~, r = trilinear mip lookup of albedo, normal, roughness at (t, lod), periodic in t
//   n_ts   = n~ / |n~|;  n = n_ts.x T_t + n_ts.y B_t + n_ts.z N   (T_t, B_t: frame of t, as
//            ps::tangentFrame; turns with `rotation`; falls back to N where n.wo < 1e-4 as the
//            path tracer does)
//   I_p    = sum over grid bins b of L_b(p) f(wo, d_b; A, n, r) (n.d_b)+ dOmega_b
//            f = A (1 - metallic) / pi + D G F / (4 (n.wo)(n.d))   (ps::MicrofacetBsdf's model)
// L_b(p) is the incident-light grid bilinearly interpolated between the grid points around p that
// see the same part with a similar normal. The diffuse term uses the bin centers (the cosine is
// linear over a bin of equal solid angle); the specular term averages the BRDF over
// specularSub x specularSub directions per bin (as IncidentLightGrid::shade does).
//
// The nvdiffrast pattern: renderLayerForward() and renderLayerBackward() share RenderLayerParams.
//
//   ps::PartGeometry geo = ps::preparePartGeometry(gbuffer, camera.position().cast<float>(),
//                                                  grid, gbuffer.mask[part], part);   // once
//   ps::RenderLayerParams p;
//   p.geometry = &geo;
//   p.albedo = maps.albedo; p.normal = maps.normal; p.roughnessValue = 0.6f;
//   p.uv = {.rotation = 0.3f, .logScale = std::log(2.0f)};
//   ps::renderLayerForward(p);                      // p.image: CV_32FC3, 0 outside the mask
//   ps::RenderLayerGradients g;
//   ps::renderLayerBackward(p, dLossdImage, g);     // g.albedo, g.normal, g.roughnessValue, g.uv
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/core/math.hpp"
#include "photoscene/raytrace/gbuffer.hpp"
#include "photoscene/raytrace/incident_light.hpp"
#include "photoscene/scene/material.hpp"

namespace ps {

/// The UV transform as the optimizer sees it (continuous, unconstrained):
/// t = R(rotation) * (exp(logScale) * uv) + offset.
struct UvParams {
  float rotation = 0.0f;  ///< radians, counter-clockwise
  float logScale = 0.0f;  ///< natural log of the isotropic scale
  Vec2f offset = Vec2f::Zero();
  /// The contract's form (degrees, scale, offset).
  UvTransform toTransform() const;
  static UvParams fromTransform(const UvTransform& t);  ///< uses the geometric mean of the scales
};

/// What the layer needs of one part in one view, computed once (geometry and lighting do not
/// change while a material is fitted). Pixels are the non-zero pixels of the mask, row-major.
struct PartGeometry {
  cv::Size imageSize;
  int part = -1;
  std::vector<cv::Point> pixels;
  struct Pixel {
    Vec2f uv = Vec2f::Zero();   ///< OBJ uv
    float footprint = 0;        ///< max(|duv/dx|, |duv/dy|) (uv units per pixel); 0 = degenerate
    Vec3f wo = Vec3f(0, 0, 1);  ///< unit direction to the camera in the local frame (T, B, N)
    float J[4] = {1, 0, 0, 1};  ///< dP/du, dP/dv projected on (T, B): [T.dpdu, T.dpdv, B.dpdu, B.dpdv]
    bool frameOk = true;        ///< false: the uv derivatives are degenerate (no rotation of normals)
  };
  std::vector<Pixel> data;
  int bins = 0;                 ///< thetaBins * phiBins
  int thetaBins = 0, phiBins = 0;
  float binSolidAngle = 0;
  std::vector<Vec3f> binDir;    ///< bin centers, local frame
  /// Interpolated incident radiance, per pixel one plane per channel (the layer's per-direction
  /// loops read it contiguously): light[lightIndex(pixel, b, c)] = light[(pixel * 3 + c) * bins + b].
  std::vector<float> light;
  size_t lightIndex(int pixel, int bin, int channel) const {
    return (static_cast<size_t>(pixel) * 3 + channel) * bins + bin;
  }
  int size() const { return static_cast<int>(pixels.size()); }
};

/// Builds the per-pixel geometry and interpolated lighting of the part `part` over `mask`.
/// @param gbuffer  from ps::renderGBuffer for the view (image size = mask size)
/// @param cameraCenter world position of the camera
/// @param grid     ps::computeIncidentLight for the same view and G-buffer
/// @param mask     CV_8UC1, gbuffer size, non-zero = pixels to render (usually gbuffer.mask[part]
///                 or the aligned mask M_aln; pixels where the G-buffer sees no surface are dropped)
PartGeometry preparePartGeometry(const GBuffer& gbuffer, const Vec3f& cameraCenter, const IncidentLightGrid& grid,
                                 const cv::Mat& mask, int part);

/// The same part seen at half the resolution (for coarse-to-fine fits): coarse pixel (x, y) covers
/// the fine pixels (2x..2x+1, 2y..2y+1) and is kept where all four are pixels of the part with
/// continuous uvs (no seam inside the block). Its uv, uv Jacobian, light and view direction are
/// the four's means, its footprint twice theirs (the mip level moves up by one), frameOk their
/// conjunction. imageSize = fine size / 2 (rounded down).
/// @param mask  if not null, receives the coarse mask (CV_8UC1, 255 on the kept pixels)
PartGeometry downsamplePartGeometry(const PartGeometry& fine, cv::Mat* mask = nullptr);

/// The same part restricted to some of its pixels (`keep`: indices into fine.pixels, each once;
/// order kept): held-back pixels, one half of a part. Same image size, lighting and bins.
PartGeometry subsetPartGeometry(const PartGeometry& fine, const std::vector<int>& keep);

/// 2 x 2 box average of a CV_32FC3 image of `fine`'s size onto `coarse`'s pixels (0 elsewhere):
/// the photo as downsamplePartGeometry's geometry sees it.
cv::Mat downsampleImage(const PartGeometry& coarse, const cv::Mat& fineImage);

struct RenderLayerWorkspace;  // opaque

struct RenderLayerParams {
  // ---- inputs ----
  const PartGeometry* geometry = nullptr;  ///< not owned
  cv::Mat albedo;     ///< CV_32FC3 N x N (N a power of two), linear RGB, row 0 = top (t_v = 1)
  cv::Mat normal;     ///< CV_32FC3 N' x N' tangent-space normals (OpenGL); empty = flat
  cv::Mat roughness;  ///< CV_32FC1 N'' x N''; empty = roughnessValue everywhere
  float roughnessValue = 0.7f;  ///< used where `roughness` is empty
  float metallic = 0.0f;        ///< homogeneous metallic in [0, 1]
  float specular = 0.5f;        ///< F0_dielectric = 0.08 * specular
  UvParams uv;
  int specularSub = 2;          ///< sub-directions per bin side for the specular term (>= 1)
  /// The specular lobe widened to the spacing of the sub-directions it is summed over:
  /// alpha_shade^2 = alpha^2 + (lobeFilter * sqrt(binSolidAngle / specularSub^2))^2, in [0, 4]
  /// (0 = off). Off, a lobe narrower than that spacing (roughness below about 0.3 with 8 x 16
  /// bins and specularSub 1) falls between the directions or on one of them: under uniform light
  /// a mirror-like metal reflects from near 0 to 38 times its directional albedo, and on a glossy
  /// part the grid's points show as bright blobs. At 1 the worst error is about 22 % (the wider
  /// lobe loses some energy: 10 % on average at specularSub 1, 3 % at 2). Measured on the
  /// real-texture yardstick it did not improve selection (modules/select/README.md), so it is off
  /// by default.
  float lobeFilter = 0.0f;
  bool filter = true;           ///< false: bilinear at level 0 (no mip)

  // ---- outputs of renderLayerForward ----
  cv::Mat image;  ///< CV_32FC3, geometry->imageSize, linear RGB; 0 outside the part's pixels

  // ---- workspace (forward -> backward) ----
  std::shared_ptr<RenderLayerWorkspace> workspace;
};

/// d loss / d inputs. Maps have the inputs' sizes (empty where the input was empty).
struct RenderLayerGradients {
  cv::Mat albedo, normal, roughness;
  float roughnessValue = 0;
  float metallic = 0;
  float rotation = 0, logScale = 0;
  Vec2f offset = Vec2f::Zero();
};

/// Renders params.image. Throws ps::Exception for missing geometry or maps of the wrong type.
void renderLayerForward(RenderLayerParams& params);

/// Given d loss / d image (CV_32FC3, image size; read only on the part's pixels), writes every
/// gradient. Requires a renderLayerForward on the same params first.
void renderLayerBackward(const RenderLayerParams& params, const cv::Mat& gradImage, RenderLayerGradients& grads);

/// The image as a list: CV_32FC3 image -> row per pixel of the part (for tests).
std::vector<Vec3f> gatherPixels(const PartGeometry& geometry, const cv::Mat& image);

}  // namespace ps
