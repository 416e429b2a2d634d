// Closed-form fits of a part's material through the render layer: a homogeneous material, the
// second round's albedo scale / offset and roughness factor of a textured one, and the
// shading-median baseline.
//
// The render layer's image of a dielectric is linear in its albedo: I(a) = I0 + a (.) D, with I0
// the specular part (no albedo) and D the diffuse response to a white albedo. So for a given
// roughness the albedo that matches the photo's mean is a closed form per channel, and only the
// roughness is searched over a few candidates.
//
// A photo coded in integers clips at 1: where a part's pixels are saturated in a channel (a
// bright orange wall's red under a warm light), their mean is less than the light and albedo
// would give, and a fit that matches it renders the part dimmer than the photo wherever the
// photo is not clipped. With the clip level given (PartView::clip), the albedo is the one whose
// render, clipped at that level, has the photo's mean (a censored mean: monotone in the albedo,
// found by bisection); where no render pixel reaches the level it is the closed form.
//
//   const ps::PartGeometry geo = ps::preparePartGeometry(gb, cam, grid, mask, part);
//   const ps::HomogeneousFit f = ps::fitHomogeneous(geo, photo, ps::roughnessGrid(7));
#pragma once

#include <limits>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/core/math.hpp"
#include "photoscene/optim/roughness_prior.hpp"
#include "photoscene/render.hpp"

namespace ps {

struct HomogeneousFit {
  Vec3f albedo = Vec3f::Constant(0.5f);  ///< linear RGB in [0, 1]
  float roughness = 0.7f;
  double loss = 0;  ///< statLoss of the fitted render against the photo
  /// the albedo that matches the photo's mean was above 1 in a channel and is clamped (logged as a
  /// warning): the light is too dim for the photo, light and albedo traded against each other
  bool albedoClamped = false;
  float unclampedMax = 0;  ///< its largest channel before the clamp
};

/// `n` roughness values evenly spaced over [0.15, 0.95] (0.15 alone for n = 1).
std::vector<float> roughnessGrid(int n);

/// How the homogeneous fit picks the roughness (issue 17, item 5). A flat material's photo says
/// something of its roughness only where the incident light predicts a highlight
/// (ps::highlightRegion); elsewhere the statistics loss moves with the roughness by noise alone
/// (measured on the yardstick's check half: 0.15 on a fabric floor whose truth is 0.82, 0.95 on a
/// concrete wall whose truth is 0.60). So:
///   - no highlight predicted: the roughness is the prior's centre, only the albedo is fitted;
///   - a highlight predicted: each candidate (clamped to the prior's range) is scored by
///     highlightWeight * L_hl + priorWeight * L_prior (fitPart's terms) without statLoss, whose
///     value falls with the roughness of a flat render whatever the photo shows (a matte floor,
///     truth 0.75: 0.09 at 0.15, 0.24 at 0.95): a visible highlight makes the part glossy, none
///     leaves it near the prior's centre.
struct HomogeneousRoughness {
  RoughnessPrior prior;  ///< roughnessPriorFor(category); the default: the generic prior
  float priorWeight = 0.01f;
  float highlightWeight = 0.1f;
  HighlightOptions highlight;
};

struct PartFitOptions;
/// The fit options' roughness terms for a homogeneous part (the generic prior, their weights);
/// std::nullopt when the options weigh neither term (roughness by statLoss).
std::optional<HomogeneousRoughness> homogeneousRoughness(const PartFitOptions& options);

/// The homogeneous material that best explains the photo over the part's pixels: per roughness
/// candidate, the albedo whose render matches the photo's mean per channel (clamped to [0, 1]);
/// the candidate with the lowest statLoss wins (with `roughness`: as HomogeneousRoughness says).
/// HomogeneousFit::loss is the chosen candidate's statLoss.
/// @param photo CV_32FC3 linear RGB in the render frame (the part's photo warped by Eq. 1)
HomogeneousFit fitHomogeneous(const PartGeometry& geometry, const cv::Mat& photo,
                              const std::vector<float>& roughnesses,
                              const std::optional<HomogeneousRoughness>& roughness = std::nullopt);

/// One view of a part, for a fit over several views: its geometry (render frame of that view)
/// and its photo there, divided by the view's exposure.
struct PartView {
  const PartGeometry* geometry = nullptr;
  cv::Mat photo;  ///< CV_32FC3 linear RGB, the view's Eq. 1 warp, divided by its exposure
  /// the level at which `photo` is clipped (1 / exposure for an 8- or 16-bit photo); infinity:
  /// never (a float photo)
  float clip = std::numeric_limits<float>::infinity();
};

/// The same fit over several views of the part at once: the albedo matches the photos' mean over
/// all their pixels (each pixel counts once, whichever view it is in), a highlight predicted in
/// any view can move the roughness, and the losses are pixel-weighted over the views. With one
/// view it is the fit above.
HomogeneousFit fitHomogeneous(const std::vector<PartView>& views,
                              const std::vector<float>& roughnesses,
                              const std::optional<HomogeneousRoughness>& roughness = std::nullopt);

/// The second round for a textured part (the maps keep their pattern).
struct TexturedRefine {
  float albedoScale = 1.0f;            ///< s: albedo = s (map + o), in [0.25, 4]
  Vec3f albedoOffset = Vec3f::Zero();  ///< o, per channel in [-0.5, 0.5]
  float roughnessFactor = 1.0f;        ///< multiplies the held roughness
  double loss = 0;                     ///< statLoss of the best candidate
};

/// Per roughness factor in `candidates` values log-spaced over [0.5, 2] (only 1 where the light
/// predicts no highlight on the part: ps::highlightRegion is empty; there the loss also has the
/// highlight term ps::highlightLoss): the one albedo scale s
/// that matches the photo's channel means by least squares, then the per-channel offset o that
/// matches each channel's mean, so the colour comes out right where the graph's colour
/// parameters could not reach it; the factor with the lowest statLoss wins.
/// @param photo   CV_32FC3 linear RGB in the render frame; @param mask CV_8UC1 M_aln
/// @param albedo  CV_32FC3 albedo map; @param normal CV_32FC3 tangent-space normal map
/// @param uv      the part's UV transform; @param roughness the held mean roughness
/// @param clip    the level at which `photo` is clipped (PartView::clip): each channel's offset
///                then matches the photo's mean with the render clipped there
TexturedRefine refineTextured(const PartGeometry& geometry, const cv::Mat& photo,
                              const cv::Mat& mask, const cv::Mat& albedo, const cv::Mat& normal,
                              const UvParams& uv, float roughness, int candidates,
                              float clip = std::numeric_limits<float>::infinity());

/// The shading-median baseline (an inverse-rendering stand-in): per channel, the median over
/// the part's pixels of photo / diffuse shading (the Lambert render with a white albedo),
/// clamped to [0, 1]; 0.5 for a channel with no shaded pixel.
Vec3f shadingMedianAlbedo(const PartGeometry& geometry, const cv::Mat& photo);

}  // namespace ps
