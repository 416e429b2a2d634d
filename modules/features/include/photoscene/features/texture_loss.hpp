// The texture-feature loss between a rendered part and its photo, and its analytic gradient.
//
//   loss = sum over groups g of  weight_g / n_g * sum_{i in g} ((D_i(render) - D_i(photo)) / nu)^2
//
// D is the descriptor of texture_descriptor.hpp computed over the same mask on both images; the
// groups are colorMean (3 entries), colorStd (3), and the four band statistics meanRe, stdRe,
// meanMag, stdMag (numScales * numOrientations entries each), each optionally multiplied by a
// per-scale weight. nu = max(mean photo luminance over the mask, 1e-3) when normalizeByTarget is
// set (the loss is then unitless and unchanged when photo and render are scaled together), else 1.
//
// Optional joint statistics (texture_ps.hpp; all weights 0 by default, and then neither computed
// nor differentiated): the same squared differences, group mean times weight, of the low-pass
// autocorrelation (psAutoLowpass), the band magnitudes' autocorrelation (psAutoMagnitude), the
// cross-orientation (psCrossOrientation) and cross-scale (psCrossScale) magnitude correlations
// (these four are correlation coefficients: not divided by nu) and the opponent colour
// statistics (psColor: 9 entries; the 6 means and standard deviations divided by nu, the 3
// correlations not).
//
// Forward and backward share one parameter struct (the nvdiffrast pattern): the caller fills the
// inputs, textureLossForward() fills the outputs and the workspace, textureLossBackward() reads
// them. The photo's descriptor is computed once, in TextureLossTarget.
//
// The gradient is exact for the computed loss (the filters, the pyramid and the masked statistics
// are differentiated analytically; the adjoint of each filter is the flipped filter with the same
// zero padding). It is non-zero only on mask pixels.
//
// Example (one step of a per-part fit):
//   ps::TextureLossTarget target(photo, partMask);           // once per part
//   ps::TextureLossParams p;
//   p.target = &target;
//   p.render = renderOfPart;                                  // CV_32FC3, photo's size
//   double loss = ps::textureLossForward(p);
//   ps::textureLossBackward(p, 1.0f, gradRender);             // d loss / d render, CV_32FC3
#pragma once

#include "photoscene/features/texture_descriptor.hpp"
#include "photoscene/features/texture_ps.hpp"

#include <opencv2/core.hpp>

#include <memory>
#include <string>
#include <vector>

namespace ps {

/// Weights of the loss's groups. A weight of 0 drops its group (and its cost in backward).
struct TextureLossWeights {
  float colorMean = 1.0f;
  float colorStd = 1.0f;
  float bandMeanRe = 0.25f;
  float bandStdRe = 1.0f;
  float bandMeanMag = 1.0f;
  float bandStdMag = 1.0f;
  /// Per-scale multipliers of the band groups; empty = all 1, else numScales entries >= 0.
  std::vector<float> scale;
  /// The joint statistics of texture_ps.hpp (0: not computed).
  float psAutoLowpass = 0.0f;
  float psAutoMagnitude = 0.0f;
  float psCrossOrientation = 0.0f;
  float psCrossScale = 0.0f;
  float psColor = 0.0f;
  /// The colour distribution (sliced Wasserstein, see the top; 0: not computed).
  float colorSliced = 0.0f;
  /// The spectral shape: each band's share of the summed band energy (meanMag^2 + stdMag^2 over
  /// the sum of it over the bands), weight times the summed squared difference of the shares.
  /// Blind to contrast (the colour groups see that), it sees how the energy spreads over scale
  /// and orientation. 0: not computed.
  float bandShape = 0.0f;
  bool anyPs() const {
    return psAutoLowpass > 0 || psAutoMagnitude > 0 || psCrossOrientation > 0 || psCrossScale > 0 ||
           psColor > 0;
  }
};

struct TextureLossOptions {
  TextureDescriptorOptions descriptor;
  TextureLossWeights weights;
  /// Lag windows of the joint statistics (used when a weights.ps* is > 0).
  TexturePsOptions ps;
  /// Divide descriptor differences by the photo's mean masked luminance (see the top).
  bool normalizeByTarget = true;
  /// The photo's pixel noise taken off its statistics: a render carries none of the photo's
  /// sensor or path-tracing noise, and without this a texture with fine grain matched the noise's
  /// band energy and beat the flat material on plain parts. The noise level per channel is read
  /// from the photo (estimatePixelNoise), its share of each statistic from a white-noise image of
  /// that level through the same mask and filters, and taken off in quadrature: the colour
  /// standard deviations and the real parts' variances by theirs, the magnitudes' second moment
  /// (meanMag^2 + stdMag^2) by its, both magnitude entries scaled alike.
  /// Off by default: on the real-texture yardstick it changed nothing that counts
  /// (modules/select/README.md, "The photo's noise taken off the target").
  bool photoNoiseFloor = false;

  bool IsValid(std::string* error) const;
};

/// The photo side of the loss: the mask, its crop, pyramid and weights, and the photo's
/// descriptor, computed once per part and reused for every render.
class TextureLossTarget {
 public:
  /// @param photo CV_32FC3, linear RGB (R first), non-negative, finite
  /// @param mask  CV_8UC1, photo's size, non-zero = the part; non-empty (else ps::Exception)
  TextureLossTarget(const cv::Mat& photo, const cv::Mat& mask,
                    const TextureLossOptions& options = {});
  ~TextureLossTarget();
  TextureLossTarget(TextureLossTarget&&) noexcept;
  TextureLossTarget& operator=(TextureLossTarget&&) noexcept;

  const TextureLossOptions& options() const;
  const TextureDescriptor& descriptor() const;  ///< the photo's descriptor
  cv::Size imageSize() const;                   ///< size renders must have
  cv::Rect crop() const;                        ///< region of the image the loss reads
  double normalizer() const;                    ///< nu
  /// The photo's joint statistics (texture_ps.hpp layout; empty when every ps weight is 0).
  const std::vector<float>& psStatistics() const;
  /// The photo's pixel noise per channel (standard deviation, linear units) taken off the
  /// statistics; 0 without options().photoNoiseFloor.
  cv::Vec3d photoNoise() const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

/// A photo's pixel noise per channel (standard deviation) over a mask: the median absolute
/// response of Immerkaer's operator [1 -2 1; -2 4 -2; 1 -2 1] (it cancels a locally linear or
/// quadratic surface) at the mask pixels whose 3 x 3 neighbourhood is in the mask, over 0.6745 * 6
/// (the median of |N(0, 1)| times the operator's L2 norm). Texture with energy at the pixel scale
/// raises it: an upper bound. 0 when fewer than `minPixels` such pixels.
/// @param photo CV_32FC3; @param mask CV_8UC1 of its size, non-zero = the region
cv::Vec3d estimatePixelNoise(const cv::Mat& photo, const cv::Mat& mask, int minPixels = 64);

/// Intermediate results of a forward pass, kept for backward (opaque).
struct TextureLossWorkspace;

/// Shared by textureLossForward and textureLossBackward.
struct TextureLossParams {
  // ---- inputs (set by the caller) ----
  const TextureLossTarget* target = nullptr;  ///< not owned; must outlive the params' use
  cv::Mat render;  ///< CV_32FC3, linear RGB, target->imageSize(); finite. Only crop() is read.

  // ---- outputs of textureLossForward ----
  double loss = 0.0;
  TextureDescriptor renderDescriptor;  ///< the render's descriptor
  /// Per-group contributions to loss: colorMean, colorStd, meanRe, stdRe, meanMag, stdMag.
  double groupLoss[6] = {0, 0, 0, 0, 0, 0};
  /// Contributions of the joint statistics: psAutoLowpass, psAutoMagnitude, psCrossOrientation,
  /// psCrossScale, psColor (0 when their weight is 0).
  double psGroupLoss[5] = {0, 0, 0, 0, 0};
  /// The render's joint statistics (texture_ps.hpp layout; empty when every ps weight is 0).
  std::vector<float> renderPs;
  /// Contribution of the colour distribution (weights.colorSliced times the distance; 0 when off).
  double slicedLoss = 0.0;
  /// Contribution of the spectral shape (weights.bandShape; 0 when off).
  double shapeLoss = 0.0;

  // ---- workspace (written by forward, read by backward) ----
  std::shared_ptr<TextureLossWorkspace> workspace;
};

/// Computes params.loss (and the other outputs) for params.render against params.target.
/// @throws ps::Exception when target is null or render has the wrong type or size
double textureLossForward(TextureLossParams& params);

/// d(gradLoss * loss) / d render, after textureLossForward on the same params.
/// @param gradRender CV_32FC3, target->imageSize(): overwritten (allocated if empty or of another
///                   size / type) unless accumulate, when the gradient is added to it. Zero outside
///                   the mask.
void textureLossBackward(const TextureLossParams& params, float gradLoss, cv::Mat& gradRender,
                         bool accumulate = false);

/// Finite-difference check of textureLossBackward at chosen pixels and channels.
struct TextureLossGradientCheck {
  double maxAbsError = 0.0;  ///< max |analytic - numeric|
  double maxRelError = 0.0;  ///< max |analytic - numeric| / max(|analytic|, |numeric|, floor)
  double floor = 0.0;        ///< the floor used: max(1e-3 * max |numeric|, 2 * noise)
  double noise = 0.0;        ///< max |numeric(step) - numeric(2 step)|: the float loss's round-off
  double maxNumeric = 0.0;   ///< max |numeric|: the scale errors compare with
  int checked = 0;
};
/// Central differences with step `step` (linear units) on render(p)[c] for every p in pixels
/// and c in {0, 1, 2}; analytic gradient from textureLossBackward. Pixels outside the mask must
/// have gradient 0 and are checked as such. Every entry is also differenced with step 2 * step; the
/// largest disagreement between the two measures the finite differences' own noise and sets the
/// floor, so the check does not depend on how a compiler orders the float sums.
TextureLossGradientCheck checkTextureLossGradient(const TextureLossTarget& target,
                                                  const cv::Mat& render,
                                                  const std::vector<cv::Point>& pixels,
                                                  double step = 1e-3);

}  // namespace ps
