// Plausible roughness and albedo (roughness_prior.hpp): the priors' table, every new term's
// gradient against finite differences (alone and through the render layer), no NaN/Inf at black,
// saturated or one-pixel inputs, and the fit on a synthetic floor: a glossy truth whose highlight
// the camera sees is fitted glossy, a matte truth is not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "photoscene/graph.hpp"
#include "photoscene/optim.hpp"
#include "photoscene/optim/roughness_prior.hpp"
// the in-memory room of the render module's tests (test-only code, shared rather than copied)
#include "../../render/test/synthetic_room.hpp"

namespace ps {
namespace {

using namespace testroom;

TEST(Optim_RoughnessPrior, fabric_and_carpet_are_never_glossy_and_every_category_has_a_prior) {
  for (const char* c : {"fabric", "carpet", "paper", "cork"}) {
    const RoughnessPrior p = roughnessPriorFor(c);
    EXPECT_GE(p.min, 0.45f) << c;
    EXPECT_GT(p.center(), 0.6f) << c;
  }
  // glossy-capable categories keep a low bound (polished marble, lacquered parquet: 0.07-0.1)
  for (const char* c : {"stone", "wood", "tile", "metal"})
    EXPECT_LE(roughnessPriorFor(c).min, 0.05f) << c;
  for (const std::string& c : materialCategories()) {
    const RoughnessPrior p = roughnessPriorFor(c);
    EXPECT_GT(p.logSigma, 0.0f) << c;
    EXPECT_LT(p.min, p.center()) << c;
    EXPECT_LE(p.center(), p.max) << c;
  }
  // the prior's minimum is at its center and it grows on both sides
  const RoughnessPrior w = roughnessPriorFor("wood");
  EXPECT_NEAR(roughnessPriorLoss(w, w.center(), nullptr), 0.0, 1e-9);
  EXPECT_GT(roughnessPriorLoss(w, 0.05f, nullptr), roughnessPriorLoss(w, 0.2f, nullptr));
  EXPECT_GT(roughnessPriorLoss(w, 0.95f, nullptr), roughnessPriorLoss(w, 0.4f, nullptr));
}

TEST(Optim_RoughnessPrior, prior_gradient_matches_finite_differences) {
  double worst = 0;
  for (const char* c : {"fabric", "wood", "stone", "metal", ""})
    for (float r : {0.03f, 0.1f, 0.35f, 0.7f, 0.99f}) {
      const RoughnessPrior p = roughnessPriorFor(c);
      double g = 0;
      roughnessPriorLoss(p, r, &g);
      const double h = 1e-4 * r;
      const double num = (roughnessPriorLoss(p, r + float(h), nullptr) -
                          roughnessPriorLoss(p, r - float(h), nullptr)) /
                         (double(r + float(h)) - double(r - float(h)));
      worst = std::max(worst, std::abs(num - g) / std::max(1e-2, std::abs(num)));
    }
  EXPECT_LT(worst, 1e-2);
  // roughness near 0 and at 0: finite
  double g = 0;
  EXPECT_TRUE(std::isfinite(roughnessPriorLoss(roughnessPriorFor("wood"), 0.0f, &g)));
  EXPECT_TRUE(std::isfinite(g));
  EXPECT_TRUE(std::isfinite(roughnessPriorLoss(roughnessPriorFor("wood"), 1e-7f, &g)));
  EXPECT_TRUE(std::isfinite(g));
}

// A photo and a render over a 12 x 10 image, the part and a highlight subset.
struct HighlightCase {
  cv::Mat photo, render;
  std::vector<cv::Point> px, hl;
};

HighlightCase highlightCase(uint64_t seed) {
  Rng rng(seed);
  HighlightCase c;
  c.photo.create(10, 12, CV_32FC3);
  c.render.create(10, 12, CV_32FC3);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 12; ++x) {
      c.photo.at<cv::Vec3f>(y, x) = cv::Vec3f(rng.uniform(), rng.uniform(), rng.uniform());
      c.render.at<cv::Vec3f>(y, x) =
          cv::Vec3f(rng.uniform(), 0.5f * rng.uniform(), 2 * rng.uniform());
    }
  for (int y = 1; y < 9; ++y)
    for (int x = 2; x < 11; ++x) {
      c.px.emplace_back(x, y);
      if (x >= 4 && x < 7 && y >= 3 && y < 5) c.hl.emplace_back(x, y);
    }
  // the photo has a highlight the render lacks
  for (const cv::Point& q : c.hl) c.photo.at<cv::Vec3f>(q) *= 3.0f;
  return c;
}

TEST(Optim_RoughnessPrior, highlight_loss_gradient_matches_finite_differences) {
  const HighlightCase c = highlightCase(4);
  cv::Mat g;
  const double l = highlightLoss(c.photo, c.render, c.px, c.hl, &g, 1.0);
  EXPECT_GT(l, 0.1);  // the photo's highlight is ~3x, the render's none
  double worst = 0;
  for (const cv::Point& p : {c.px[0], c.hl[1], c.px[40], c.hl[4]})
    for (int ch = 0; ch < 3; ++ch) {
      const double h = 1e-3;
      cv::Mat a = c.render.clone(), b = c.render.clone();
      a.at<cv::Vec3f>(p)[ch] += h;
      b.at<cv::Vec3f>(p)[ch] -= h;
      const double num = (highlightLoss(c.photo, a, c.px, c.hl, nullptr) -
                          highlightLoss(c.photo, b, c.px, c.hl, nullptr)) /
                         (2 * h);
      worst =
          std::max(worst, std::abs(num - g.at<cv::Vec3f>(p)[ch]) / std::max(1e-3, std::abs(num)));
    }
  EXPECT_LT(worst, 1e-2);
  // brightening the render's highlight region lowers the loss (the gradient there is negative)
  EXPECT_LT(g.at<cv::Vec3f>(c.hl[0])[0], 0.0f);
  // no highlight region: 0, no gradient
  cv::Mat g0;
  EXPECT_EQ(highlightLoss(c.photo, c.render, c.px, {}, &g0), 0.0);
  EXPECT_TRUE(g0.empty());
}

TEST(Optim_RoughnessPrior,
     albedo_ceiling_gradient_matches_finite_differences_and_is_zero_below_the_knee) {
  Rng rng(9);
  cv::Mat a(6, 6, CV_32FC3);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x)
      a.at<cv::Vec3f>(y, x) = cv::Vec3f(0.8f + 0.25f * rng.uniform(), rng.uniform(), 0.5f);
  cv::Mat g;
  const double l = albedoCeilingLoss(a, 0.9f, &g);
  EXPECT_GT(l, 0.0);
  double worst = 0;
  int above = 0;
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = a.at<cv::Vec3f>(y, x)[c];
        if (std::abs(v - 0.9f) < 2e-3f) continue;  // the kink
        above += v > 0.9f;
        const double h = 1e-3;
        cv::Mat p = a.clone(), m = a.clone();
        p.at<cv::Vec3f>(y, x)[c] += h;
        m.at<cv::Vec3f>(y, x)[c] -= h;
        const double num =
            (albedoCeilingLoss(p, 0.9f, nullptr) - albedoCeilingLoss(m, 0.9f, nullptr)) / (2 * h);
        worst = std::max(worst,
                         std::abs(num - g.at<cv::Vec3f>(y, x)[c]) / std::max(1e-4, std::abs(num)));
        if (v < 0.9f) {
          EXPECT_EQ(g.at<cv::Vec3f>(y, x)[c], 0.0f);
        }
      }
  EXPECT_GT(above, 5);
  EXPECT_LT(worst, 1e-2);
  const cv::Vec3f f = albedoFractionAtCeiling(cv::Mat(4, 4, CV_32FC3, cv::Scalar(1.0, 0.5, 0.995)));
  EXPECT_FLOAT_EQ(f[0], 1.0f);
  EXPECT_FLOAT_EQ(f[1], 0.0f);
  EXPECT_FLOAT_EQ(f[2], 1.0f);
}

TEST(Optim_RoughnessPrior,
     no_nan_or_inf_at_black_saturated_pixels_one_pixel_masks_and_roughness_near_zero) {
  const HighlightCase c = highlightCase(5);
  const cv::Mat black = cv::Mat::zeros(c.photo.size(), CV_32FC3);
  const cv::Mat white(c.photo.size(), CV_32FC3, cv::Scalar::all(1.0));
  const cv::Mat hot(c.photo.size(), CV_32FC3, cv::Scalar::all(1e4));
  const std::vector<cv::Point> one = {c.px[7]};
  for (const cv::Mat* p : {&black, &white, &hot, &c.photo})
    for (const cv::Mat* r : {&black, &white, &hot, &c.render})
      for (const auto* region : {&c.px, &one}) {
        const std::vector<cv::Point>& hl = region == &one ? one : c.hl;
        cv::Mat g;
        const double l = highlightLoss(*p, *r, *region, hl, &g);
        EXPECT_TRUE(std::isfinite(l));
        EXPECT_TRUE(cv::checkRange(g));
      }
  cv::Mat g;
  EXPECT_TRUE(std::isfinite(albedoCeilingLoss(white, 0.9f, &g)));
  EXPECT_TRUE(cv::checkRange(g));
  EXPECT_TRUE(std::isfinite(albedoCeilingLoss(black, 0.9f, &g)));
}

// ---- through the render layer, on a real G-buffer and incident-light grid

// The synthetic room with its light moved so that the camera sees its mirror image on the floor
// (near the bottom of the image, in front of the box).
Room highlightRoom(int W, int H) {
  Room room = makeRoom(W, H);
  room.scene.lights.area[0].center = Vec3f(3.2f, 2.49f, 0.3f);
  return room;
}

/// The room's floor path-traced under `mats` (spp, seed) and its part geometry (incident grid
/// with `gridSamples` samples per bin).
struct FloorPhoto {
  cv::Mat photo;
  PartGeometry geo;
};
FloorPhoto floorPhoto(const Room& room, const std::vector<PartMaterial>& mats, int spp,
                      uint64_t seed, int gridSamples) {
  const PathTracer tracer(room.scene, mats);
  RenderOptions ro;
  ro.spp = spp;
  ro.seed = seed;
  FloorPhoto f;
  f.photo = tracer.render(room.camera, ro);
  const testroom::View view = prepareView(tracer, room.camera, 8, gridSamples, 9);
  f.geo = preparePartGeometry(view.gbuffer, room.camera.position().cast<float>(), view.grid,
                              view.gbuffer.mask[room.floor], room.floor);
  return f;
}

TEST(Optim_RoughnessPrior,
     highlight_term_roughness_gradient_through_the_render_layer_matches_finite_differences) {
  Room room = highlightRoom(64, 48);
  std::vector<PartMaterial> mats = {lambert("floor", 0.5f), lambert("walls", 0.7f),
                                    lambert("ceiling", 0.8f), lambert("box", 0.6f)};
  mats[room.floor].roughness = 0.15f;
  mats[room.floor].specular = 0.5f;
  const FloorPhoto fp = floorPhoto(room, mats, 16, 0, 2);
  const cv::Mat& photo = fp.photo;
  const PartGeometry& geo = fp.geo;
  const std::vector<cv::Point> hl = highlightRegion(geo);
  ASSERT_GT(hl.size(), 0u) << "the light should predict a highlight on the floor";
  const RoughnessPrior prior = roughnessPriorFor("wood");
  const cv::Mat albedo(4, 4, CV_32FC3, cv::Scalar(0.6, 0.45, 0.3));
  auto lossAt = [&](float r, float* grad) {
    RenderLayerParams p;
    p.geometry = &geo;
    p.albedo = albedo;
    p.roughnessValue = r;
    renderLayerForward(p);
    cv::Mat g;
    const double lh = highlightLoss(photo, p.image, geo.pixels, hl, grad ? &g : nullptr, 1.0);
    double gp = 0;
    const double lp = 0.05 * roughnessPriorLoss(prior, r, &gp);
    if (grad) {
      RenderLayerGradients gr;
      renderLayerBackward(p, g, gr);
      *grad = gr.roughnessValue + static_cast<float>(0.05 * gp);
    }
    return lh + lp;
  };
  double worst = 0;
  for (float r : {0.2f, 0.45f, 0.8f}) {
    float ana = 0;
    lossAt(r, &ana);
    double best = 1e30, numBest = 0;
    for (double h : {1e-3, 2.5e-4}) {
      const double num = (lossAt(r + float(h), nullptr) - lossAt(r - float(h), nullptr)) / (2 * h);
      if (std::abs(num - ana) < best) best = std::abs(num - ana), numBest = num;
    }
    std::printf("r %.2f: analytic %+.5f numeric %+.5f\n", r, ana, numBest);
    worst = std::max(worst, best / std::max({std::abs(numBest), std::abs(double(ana)), 1e-2}));
    // the photo's surface is glossy (0.15): above it the highlight term pulls roughness down
    if (r >= 0.45f) {
      EXPECT_GT(numBest, 0.0) << r;
    }
  }
  EXPECT_LT(worst, 2e-2);
}

// The fit on a synthetic floor (wood_planks at known parameters, 160 x 120, 128 spp), with the
// roughness map of the truth replaced by a constant: glossy (0.08, the light's mirror image on the
// floor in view) and matte (0.75).
struct RoughnessRecovery {
  float fitted = 0, fittedWithout = 0;
  int highlightPixels = 0;
};

RoughnessRecovery fitRoughness(float truthRoughness) {
  const int W = 160, H = 120;
  const GraphLibrary lib = GraphLibrary::load();
  MaterialGraph truth = lib.create("wood_planks");
  Room room = highlightRoom(W, H);
  std::vector<PartMaterial> mats = {lambert("floor", 0.5f), lambert("walls", 0.7f),
                                    lambert("ceiling", 0.8f), lambert("box", 0.6f)};
  const MaterialMaps tm = truth.evaluate(256, MapSet::of({MapKind::Albedo, MapKind::Normal}));
  PartMaterial& m = mats[room.floor];
  m.albedoMap = FloatTexture(tm.albedo);
  m.normalMap = FloatTexture(tm.normal);
  m.roughness = truthRoughness;
  m.specular = 0.5f;
  UvParams uv;
  uv.logScale = std::log(0.5f);
  m.uv = uv.toTransform();
  const PathTracer tracer(room.scene, mats);
  RenderOptions ro;
  ro.spp = 128;
  ro.seed = 3;
  ro.filter = PixelFilter::Box;
  ro.filterWidth = 1.0f;
  const cv::Mat photo = tracer.render(room.camera, ro);
  const testroom::View view = prepareView(tracer, room.camera, 8, 8, 9);
  const int part = room.floor;
  const PartGeometry geo = preparePartGeometry(view.gbuffer, room.camera.position().cast<float>(),
                                               view.grid, view.gbuffer.mask[part], part);
  const TextureLossTarget target(photo, view.gbuffer.mask[part]);
  PartFitOptions o = PartFitOptions::preset("fast");
  const PartFitResult r = fitPart(lib.create("wood_planks"), geo, photo, target, o);
  PartFitOptions off = o;
  off.roughnessPriorWeight = off.highlightWeight = off.albedoCeilingWeight = 0.0f;
  off.roughnessCandidates = 0;  // the fit before these terms (for the log, not asserted)
  const PartFitResult r0 = fitPart(lib.create("wood_planks"), geo, photo, target, off);
  std::printf(
      "truth roughness %.2f: fitted %.3f (highlight region %d px, loss prior %.4f highlight %.4f), "
      "without them and the line search %.3f\n",
      truthRoughness, r.roughness, r.highlightPixels, r.lossPrior, r.lossHighlight, r0.roughness);
  EXPECT_TRUE(std::isfinite(r.loss));
  EXPECT_TRUE(cv::checkRange(r.render));
  return {r.roughness, r0.roughness, r.highlightPixels};
}

TEST(Optim_RoughnessPrior, glossy_truth_with_a_visible_highlight_is_fitted_glossy) {
  const RoughnessRecovery g = fitRoughness(0.08f);
  EXPECT_GT(g.highlightPixels, 0);
  EXPECT_LT(g.fitted, 0.2f);
}

TEST(Optim_RoughnessPrior, matte_truth_is_not_fitted_glossy) {
  const RoughnessRecovery m = fitRoughness(0.75f);
  EXPECT_GT(m.highlightPixels, 0);  // the light predicts a highlight; the photo shows none
  EXPECT_GT(m.fitted, 0.5f);
}

// A homogeneous floor under a light that predicts a highlight on it: its roughness follows the
// highlight (glossy 0.1, matte 0.75); without a predicted highlight the photo says nothing of the
// roughness and the prior's centre is kept (by statLoss alone it ran to the grid's ends).
float homogeneousRoughnessOf(float truth, bool highlightLight, int* highlightPixels,
                             float highlightMinRatio = HighlightOptions{}.minRatio) {
  Room room = highlightLight ? highlightRoom(96, 72) : makeRoom(96, 72);
  std::vector<PartMaterial> mats = {lambert("floor", 0.5f), lambert("walls", 0.7f),
                                    lambert("ceiling", 0.8f), lambert("box", 0.6f)};
  mats[room.floor].albedo = Vec3f(0.45f, 0.35f, 0.25f);
  mats[room.floor].roughness = truth;
  mats[room.floor].specular = 0.5f;
  const FloorPhoto fp = floorPhoto(room, mats, 64, 7, 4);
  const cv::Mat& photo = fp.photo;
  const PartGeometry& geo = fp.geo;
  HomogeneousRoughness rough = *homogeneousRoughness(PartFitOptions::preset("fast"));
  rough.highlight.minRatio = highlightMinRatio;
  *highlightPixels = static_cast<int>(highlightRegion(geo, rough.highlight).size());
  const HomogeneousFit f = fitHomogeneous(geo, photo, roughnessGrid(7), rough);
  const HomogeneousFit plain = fitHomogeneous(geo, photo, roughnessGrid(7));
  std::printf("truth %.2f (%s): roughness %.3f, by statLoss alone %.3f; albedo %.3f %.3f %.3f\n",
              truth, *highlightPixels > 0 ? "highlight predicted" : "no highlight", f.roughness,
              plain.roughness, f.albedo.x(), f.albedo.y(), f.albedo.z());
  EXPECT_TRUE(std::isfinite(f.loss));
  EXPECT_TRUE(f.albedo.allFinite());
  return f.roughness;
}

TEST(Optim_RoughnessPrior, homogeneous_roughness_follows_a_predicted_highlight_else_the_prior) {
  int hl = 0;
  EXPECT_LE(homogeneousRoughnessOf(0.1f, true, &hl), 0.3f);
  EXPECT_GT(hl, 0);
  // matte: no highlight in the photo where the light predicts one; 0.15 by statLoss alone
  // (measured: 0.417, the prior's centre being 0.48: a highlight this faint is invisible at 0.4)
  EXPECT_GE(homogeneousRoughnessOf(0.75f, true, &hl), 0.4f);
  const float other = homogeneousRoughnessOf(0.75f, false, &hl);
  if (hl == 0) {
    EXPECT_FLOAT_EQ(other, roughnessPriorFor("").center());
  } else {
    EXPECT_GE(other, 0.4f);  // this room's light predicts a highlight too: it decides (0.55)
  }
  // no highlight predicted (a region threshold no pixel reaches): the glossy floor's photo says
  // nothing the rule reads, and the prior's centre is kept
  EXPECT_FLOAT_EQ(homogeneousRoughnessOf(0.1f, true, &hl, 1e9f), roughnessPriorFor("").center());
  EXPECT_EQ(hl, 0);
}

}  // namespace
}  // namespace ps

namespace ps {
namespace {

// A part seen in two views: the fit over both pools their pixels. With the same albedo in both
// photos it is each view's fit; with one view's photo 20 % brighter (an exposure error) it lands
// between them, weighted by pixels.
TEST(Optim_RoughnessPrior, homogeneous_fit_over_several_views_pools_their_pixels) {
  Room room = makeRoom(64, 48);
  std::vector<PartMaterial> mats = {lambert("floor", 0.5f), lambert("walls", 0.7f),
                                    lambert("ceiling", 0.8f), lambert("box", 0.6f)};
  mats[room.floor].albedo = Vec3f(0.45f, 0.35f, 0.25f);
  const FloorPhoto fp = floorPhoto(room, mats, 64, 7, 4);
  const HomogeneousRoughness rough = *homogeneousRoughness(PartFitOptions::preset("fast"));
  const HomogeneousFit a = fitHomogeneous(fp.geo, fp.photo, roughnessGrid(5), rough);
  const HomogeneousFit same =
      fitHomogeneous({{&fp.geo, fp.photo}, {&fp.geo, fp.photo}}, roughnessGrid(5), rough);
  const HomogeneousFit brighter =
      fitHomogeneous({{&fp.geo, fp.photo}, {&fp.geo, fp.photo * 1.2}}, roughnessGrid(5), rough);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(same.albedo[c], a.albedo[c], 1e-5f) << c;
    EXPECT_GT(brighter.albedo[c], 1.05f * a.albedo[c]) << c;
    EXPECT_LT(brighter.albedo[c], 1.15f * a.albedo[c]) << c;
  }
  EXPECT_FLOAT_EQ(same.roughness, a.roughness);
  EXPECT_TRUE(std::isfinite(brighter.loss));
}

// fitHomogeneous flags (and logs) an albedo that must exceed 1 to match the photo and stays finite
// at black and saturated photos; refineTextured stays finite at a black photo.
TEST(Optim_RoughnessPrior, homogeneous_fit_flags_a_clamped_albedo_and_stays_finite) {
  Room room = makeRoom(64, 48);
  const std::vector<PartMaterial> mats = {lambert("floor", 0.5f), lambert("walls", 0.7f),
                                          lambert("ceiling", 0.8f), lambert("box", 0.6f)};
  const PathTracer tracer(room.scene, mats);
  const testroom::View view = prepareView(tracer, room.camera, 8, 2, 9);
  const int part = room.floor;
  const PartGeometry geo = preparePartGeometry(view.gbuffer, room.camera.position().cast<float>(),
                                               view.grid, view.gbuffer.mask[part], part);
  const cv::Size size = view.gbuffer.mask[part].size();
  const cv::Mat hot(size, CV_32FC3, cv::Scalar::all(50.0)), black = cv::Mat::zeros(size, CV_32FC3);
  const HomogeneousFit h = fitHomogeneous(geo, hot, roughnessGrid(5));
  EXPECT_TRUE(h.albedoClamped);
  EXPECT_GT(h.unclampedMax, 1.0f);
  EXPECT_LE(h.albedo.maxCoeff(), 1.0f);
  EXPECT_TRUE(std::isfinite(h.loss));
  const HomogeneousFit b = fitHomogeneous(geo, black, roughnessGrid(5));
  EXPECT_FALSE(b.albedoClamped);
  EXPECT_TRUE(std::isfinite(b.loss));
  EXPECT_TRUE(b.albedo.allFinite());
  // with the roughness terms too (black and saturated photos)
  const HomogeneousRoughness rough = *homogeneousRoughness(PartFitOptions::preset("fast"));
  for (const cv::Mat* photo : {&hot, &black}) {
    const HomogeneousFit r = fitHomogeneous(geo, *photo, roughnessGrid(5), rough);
    EXPECT_TRUE(std::isfinite(r.loss));
    EXPECT_TRUE(r.albedo.allFinite());
    EXPECT_TRUE(std::isfinite(r.roughness));
  }
  // over two views, one a black photo: finite, and the black view pulls the albedo down
  const HomogeneousFit one = fitHomogeneous(geo, hot * 0.001, roughnessGrid(5));
  const HomogeneousFit two = fitHomogeneous({{&geo, hot * 0.001}, {&geo, black}}, roughnessGrid(5));
  EXPECT_FALSE(one.albedoClamped);
  for (int c = 0; c < 3; ++c) EXPECT_LT(two.albedo[c], 0.6f * one.albedo[c]);
  EXPECT_TRUE(std::isfinite(two.loss));
  EXPECT_TRUE(two.albedo.allFinite());
  // the refine stays finite at a black photo (its highlight term included)
  const cv::Mat albedo(8, 8, CV_32FC3, cv::Scalar::all(0.5)),
      normal(8, 8, CV_32FC3, cv::Scalar(0, 0, 1));
  const TexturedRefine r =
      refineTextured(geo, black, view.gbuffer.mask[part], albedo, normal, UvParams{}, 0.3f, 5);
  EXPECT_TRUE(std::isfinite(r.loss));
  EXPECT_TRUE(std::isfinite(r.roughnessFactor));
}

}  // namespace
}  // namespace ps
