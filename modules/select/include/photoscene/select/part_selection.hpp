// Selecting a graph for a part seen in a photo, and the observation model the bank trains on.
//
// A photographed part differs from the bank's canonical patches in four ways: perspective (the
// texture's scale changes across a floor), smooth shading gradients (light falloff, a wall lit
// from one side), the mask's shape, and the camera (blur, noise, low resolution). The query
// therefore goes through `preparePartTexture`:
//
//   1. photo / shading where the caller has a shading image (incident irradiance), else photo;
//   2. the mask eroded by one pixel (edge pixels mix with the neighbouring part) when enough
//      remains;
//   3. with G-buffer UVs: the mask split into UV-continuous pieces (faces: neighbours whose UVs
//      jump by more than 4 median pixel footprints are apart; pieces under 32 px dropped), each
//      piece divided by its own smooth luminance shading estimate (removeSmoothShading, a masked
//      Gaussian blur of `ExemplarBankOptions::shadingSigma` pixels) and brought to the part's
//      pixel-weighted mean level (one material, one albedo on every face), so shading gradients
//      and the shading jumps between faces are not read as texture; then the pixels splatted into texture
//      space (align::unwarpToTexture) at the density of the coarser pixel footprints
//      (`footprintPercentile`), so the far end of a floor still covers its texels, and one-texel
//      holes closed and filled. This removes the perspective: one texture period spans the same
//      number of texels everywhere;
//   4. without UVs: the photo frame, cropped to the mask, divided by its smooth shading.
//
// The bank's canonical exemplars go through step 4 and its observed exemplars through all of it
// (`renderObservedPlane` draws a graph on a tilted plane with UVs, a shading gradient,
// blur, noise and an odd mask), so query and exemplars are described alike.
//
//   ps::ExemplarBank bank = ps::ExemplarBank::loadOrBuild(lib, {}, cacheFolder);
//   ps::GraphChoice c = ps::selectForPart(bank, photo, partMask, gbuffer.uv);
//   std::string graph = c.graph;  // e.g. "wood_planks"; c.votes holds the runners-up
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "photoscene/core/rng.hpp"
#include "photoscene/select/exemplar_bank.hpp"

namespace ps {

struct PartSelectionOptions {
  int k = 21;                  ///< neighbours that vote
  bool categoryFirst = false;  ///< ExemplarBank::select's category-first vote
  bool distinctDraws = false;  ///< ExemplarBank::select: the k nearest draws vote, not rows
  bool unwarp = true;          ///< query in texture space when UVs are given
  /// The unwarped texture's density follows this percentile of the pixels' UV footprints (0.5:
  /// one texel per median pixel; higher: coarser texels, fewer holes where the part is far).
  double footprintPercentile = 0.75;
  int maxTextureSize = 384;  ///< cap on the unwarped texture's larger side (texels)
  int erodePixels = 1;       ///< mask erosion before the query (kept only if half remains)
  /// Only graphs of this category vote (ExemplarBank::selectInCategory; categoryFirst and
  /// distinctDraws do not apply); empty: every graph.
  std::string category;
  bool IsValid(std::string* error) const;
};

/// A part's texture, prepared for the key.
struct PartTexture {
  cv::Mat image;  ///< CV_32FC3, linear RGB divided by the smooth shading estimate (mean level ~ the
                  ///< input's)
  cv::Mat mask;   ///< CV_8UC1, 255 where `image` is defined, same size
  bool unwarped = false;  ///< true: texture space; false: the photo frame, cropped to the mask
};

/// Divides `image` by a smooth estimate of its shading: the masked Gaussian blur (normalized
/// convolution, `sigma` pixels) of luminance, relative to its masked mean. A texture period much
/// shorter than sigma passes; a gradient across the region is removed. sigma <= 0: a copy.
/// @param image CV_32FC3 linear RGB, non-negative; @param mask CV_8UC1, same size
/// @return CV_32FC3, same size; 0 outside the mask
cv::Mat removeSmoothShading(const cv::Mat& image, const cv::Mat& mask, double sigma);

/// Steps 1-4 above.
/// @param photo   CV_32FC3 linear RGB (any exposure), the frame of `mask` and `uv`
/// @param mask    CV_8UC1, non-zero = the part's pixels (at least one)
/// @param uv      CV_32FC2 G-buffer UVs (OBJ convention, v up) in the same frame, or empty: the
///                query stays in the photo frame (no perspective removal)
/// @param shading CV_32FC3 or CV_32FC1 shading (irradiance) in the same frame, or empty
/// @param shadingSigma pixels of the smooth shading estimate (use the bank's)
PartTexture preparePartTexture(const cv::Mat& photo, const cv::Mat& mask, const cv::Mat& uv,
                               const cv::Mat& shading, double shadingSigma,
                               const PartSelectionOptions& options = {});

/// The graph for a part: its prepared texture's key (with the bank's key options) voted on by
/// the bank (ExemplarBank::select). Deterministic. Parts below homogeneousThreshold() should not
/// be passed (the caller gives them the homogeneous material, as the paper does).
/// @param photo, mask, uv, shading as preparePartTexture (uv empty: photo-frame query)
GraphChoice selectForPart(const ExemplarBank& bank, const cv::Mat& photo, const cv::Mat& mask,
                          const cv::Mat& uv, const cv::Mat& shading = cv::Mat(),
                          const PartSelectionOptions& options = {});

/// How a graph is observed on a plane, for the bank's observed exemplars and the held-out test.
struct ObservedPlaneParams {
  int width = 128, height = 96;  ///< image size (pixels)
  float tiltDeg = 0;             ///< plane normal from the view axis (0: frontal)
  float yawDeg = 0;              ///< direction of the tilt in the image
  float repeats = 3;             ///< texture repeats across the image width at its center
  float rotationDeg = 0;         ///< in-plane texture rotation
  cv::Vec3f lightColor = {1, 1, 1};
  float gradient = 0;    ///< shading gradient: log-luminance change across the image
  float blurSigma = 0;   ///< camera blur (pixels)
  float noise = 0;       ///< relative Gaussian noise (std / value)
  bool oddMask = false;  ///< cut the plane by a random ellipse-and-notch mask
  uint64_t seed = 0;     ///< noise, gradient direction and mask shape
};

struct ObservedPlane {
  cv::Mat image;  ///< CV_32FC3 linear RGB
  cv::Mat uv;     ///< CV_32FC2 plane UVs (1 unit = the image width at the center), v up
  cv::Mat mask;   ///< CV_8UC1
};

/// Renders material maps (albedo, normal) on a plane seen in perspective (60-degree horizontal
/// field of view): texture coordinate t = R(rotationDeg) * (repeats * uv), mip-mapped, 2 x 2
/// supersampled, Lambert + ambient under a key light, times exp(gradient * ramp), then blurred
/// and noised. Pixels past a grazing angle of 80 degrees are masked out.
ObservedPlane renderObservedPlane(const MaterialMaps& maps, const ObservedPlaneParams& params);

/// Random observation parameters over the ranges of `ExemplarBankOptions::observation`.
ObservedPlaneParams randomObservation(const ObservationRanges& ranges, Rng& rng);

}  // namespace ps
