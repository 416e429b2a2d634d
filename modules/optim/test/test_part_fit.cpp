// The part fit: gradients through the whole chain (graph parameters -> maps -> render layer ->
// stat + texture loss) against finite differences, and recovery of a known material, UV transform
// and albedo from a path-traced synthetic photo.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdlib>
#include <cstdio>

#include "photoscene/features.hpp"
#include "photoscene/graph.hpp"
#include "photoscene/optim.hpp"
// the in-memory room of the render module's tests (test-only code, shared rather than copied)
#include "../../render/test/synthetic_room.hpp"

namespace ps {
namespace {

using namespace testroom;

void writePng(const std::string& path, const cv::Mat& linear) {
  cv::Mat out(linear.size(), CV_8UC3);
  for (int y = 0; y < linear.rows; ++y)
    for (int x = 0; x < linear.cols; ++x) {
      const cv::Vec3f v = linear.at<cv::Vec3f>(y, x);
      for (int c = 0; c < 3; ++c)
        out.at<cv::Vec3b>(y, x)[2 - c] = cv::saturate_cast<uint8_t>(255.0f * std::pow(std::max(0.0f, v[c]), 1 / 2.2f));
    }
  cv::imwrite(path, out);
}

// The truth: wood planks with perturbed continuous parameters (discrete ones at their defaults,
// which a continuous fit cannot move).
std::vector<float> truthValues(const MaterialGraph& g, uint64_t seed, float spread) {
  std::vector<float> v = g.randomValues(seed, spread);
  const std::vector<float> d = g.defaultValues();
  const std::vector<uint8_t> diff = g.differentiableMask();
  for (size_t i = 0; i < v.size(); ++i)
    if (!diff[i]) v[i] = d[i];
  return v;
}

struct Synthetic {
  Room room;
  std::vector<PartMaterial> mats;
  cv::Mat photo;
  testroom::View view;
  MaterialMaps truthMaps;
};

Synthetic makeSynthetic(MaterialGraph& truth, const UvParams& uv, int W, int H, int spp, int stride, int spb) {
  Synthetic s;
  s.room = makeRoom(W, H);
  s.mats = {lambert("floor", 0.5f), lambert("walls", 0.7f), lambert("ceiling", 0.8f), lambert("box", 0.6f)};
  s.truthMaps = truth.evaluate(256, MapSet::of({MapKind::Albedo, MapKind::Normal, MapKind::Roughness}));
  PartMaterial& m = s.mats[s.room.floor];
  m.albedoMap = FloatTexture(s.truthMaps.albedo);
  m.normalMap = FloatTexture(s.truthMaps.normal);
  m.roughnessMap = FloatTexture(s.truthMaps.roughness);
  m.specular = 0.5f;
  m.uv = uv.toTransform();
  const PathTracer tracer(s.room.scene, s.mats);
  RenderOptions ro;
  ro.spp = spp;
  ro.seed = 3;
  ro.filter = PixelFilter::Box;  // a camera-like 1-pixel box (the layer filters over the pixel footprint)
  ro.filterWidth = 1.0f;
  s.photo = tracer.render(s.room.camera, ro);
  s.view = prepareView(tracer, s.room.camera, stride, spb, 9);
  return s;
}

TEST(Optim_PartFit, stat_loss_gradient_matches_finite_differences) {
  Rng rng(4);
  cv::Mat photo(10, 12, CV_32FC3), render(10, 12, CV_32FC3);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 12; ++x) {
      photo.at<cv::Vec3f>(y, x) = cv::Vec3f(rng.uniform(), rng.uniform(), rng.uniform());
      render.at<cv::Vec3f>(y, x) = cv::Vec3f(rng.uniform(), 0.5f * rng.uniform(), 2 * rng.uniform());
    }
  std::vector<cv::Point> px;
  for (int y = 1; y < 9; ++y)
    for (int x = 2; x < 11; ++x) px.emplace_back(x, y);
  cv::Mat g;
  statLoss(photo, render, px, &g);
  double maxErr = 0;
  for (const cv::Point& p : {px[0], px[17], px[40]})
    for (int c = 0; c < 3; ++c) {
      const double h = 1e-3;
      cv::Mat a = render.clone(), b = render.clone();
      a.at<cv::Vec3f>(p)[c] += h;
      b.at<cv::Vec3f>(p)[c] -= h;
      const double num = (statLoss(photo, a, px, nullptr) - statLoss(photo, b, px, nullptr)) / (2 * h);
      maxErr = std::max(maxErr, std::abs(num - g.at<cv::Vec3f>(p)[c]) / std::max(1e-3, std::abs(num)));
    }
  EXPECT_LT(maxErr, 1e-2);
}

// With the photo's pixel noise given, a noise-free render of the right colour matches the noisy
// photo: the variance term compares what is left of the photo's variance (none here), and the
// gradient still matches central differences.
TEST(Optim_PartFit, stat_loss_takes_the_photos_noise_off_its_variance) {
  Rng rng(9);
  const cv::Vec3f colour(0.4f, 0.3f, 0.2f);
  const double sigma = 0.04;
  cv::Mat photo(40, 40, CV_32FC3), flat(40, 40, CV_32FC3, cv::Scalar(colour[0], colour[1], colour[2]));
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x)
      for (int c = 0; c < 3; ++c)
        photo.at<cv::Vec3f>(y, x)[c] = colour[c] + static_cast<float>(sigma * rng.normal());
  std::vector<cv::Point> px;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) px.emplace_back(x, y);
  const cv::Vec3d noise = estimatePixelNoise(photo, cv::Mat(photo.size(), CV_8UC1, cv::Scalar(255)));
  const double without = statLoss(photo, flat, px, nullptr);
  const double with = statLoss(photo, flat, px, nullptr, noise);
  EXPECT_LT(with, 0.25 * without) << without << " -> " << with;
  cv::Mat render = flat + cv::Scalar::all(0.01), g;
  render.at<cv::Vec3f>(5, 5) += cv::Vec3f(0.2f, -0.1f, 0.05f);
  statLoss(photo, render, px, &g, noise);
  const double h = 1e-3;
  for (int c = 0; c < 3; ++c) {
    cv::Mat a = render.clone(), b = render.clone();
    a.at<cv::Vec3f>(5, 5)[c] += h;
    b.at<cv::Vec3f>(5, 5)[c] -= h;
    const double num =
        (statLoss(photo, a, px, nullptr, noise) - statLoss(photo, b, px, nullptr, noise)) / (2 * h);
    EXPECT_NEAR(num, g.at<cv::Vec3f>(5, 5)[c], 1e-2 * std::max(1e-3, std::abs(num)));
  }
}

// The worst relative error of the chain's gradient (every continuous graph parameter, the four UV
// parameters) against central differences; `joint`: the texture loss with every joint statistic
// of features/texture_ps.hpp weighted, plus the placement term (which sees the UV offset).
double chainGradientWorst(bool joint, int* checkedOut) {
  const GraphLibrary lib = GraphLibrary::load();
  MaterialGraph truth = lib.create("wood_planks");
  truth.setValues(truthValues(truth, 5, 0.4f));
  UvParams uvTrue;
  uvTrue.rotation = 0.5f;
  Synthetic s = makeSynthetic(truth, uvTrue, 64, 48, 16, 8, 2);
  const int part = s.room.floor;
  const PartGeometry geo = preparePartGeometry(s.view.gbuffer, s.room.camera.position().cast<float>(), s.view.grid,
                                               s.view.gbuffer.mask[part], part);
  TextureLossOptions texOptions;
  if (joint) {
    TextureLossWeights& w = texOptions.weights;
    w.psAutoLowpass = w.psAutoMagnitude = w.psCrossOrientation = w.psCrossScale = w.psColor = 0.05f;
  }
  const TextureLossTarget target(s.photo, s.view.gbuffer.mask[part], texOptions);
  const PlacementLossTarget placement(s.photo, s.view.gbuffer.mask[part], PlacementLossOptions{1.5});
  MaterialGraph g = lib.create("wood_planks");
  const int mapSize = 64;
  auto lossAt = [&](const std::vector<float>& values, const UvParams& uv, RenderLayerGradients* grads, std::vector<float>* dv) {
    g.setValues(values);
    const MaterialMaps m = g.evaluate(mapSize, MapSet::of({MapKind::Albedo, MapKind::Normal}));
    RenderLayerParams p;
    p.geometry = &geo;
    p.albedo = m.albedo;
    p.normal = m.normal;
    p.roughnessValue = 0.6f;
    p.uv = uv;
    renderLayerForward(p);
    TextureLossParams tp;
    tp.target = &target;
    tp.render = p.image;
    double loss = textureLossForward(tp);  // smooth (the stat loss has |.| kinks)
    const float placementWeight = 0.01f;
    if (joint) loss += placementWeight * placementLoss(placement, p.image);
    if (grads) {
      cv::Mat gr;
      textureLossBackward(tp, 1.0f, gr);
      if (joint) placementLoss(placement, p.image, &gr, placementWeight, true);
      renderLayerBackward(p, gr, *grads);
      MaterialMaps dm;
      dm.albedo = grads->albedo;
      dm.normal = grads->normal;
      *dv = g.backward(dm);
    }
    return loss;
  };
  std::vector<float> v0 = g.defaultValues();
  UvParams uv0;
  uv0.rotation = 0.2f;
  uv0.logScale = 0.1f;
  RenderLayerGradients grads;
  std::vector<float> dv;
  lossAt(v0, uv0, &grads, &dv);
  int checked = 0;
  double worst = 0;
  const auto& params = g.parameters();
  const std::vector<uint8_t> diff = g.differentiableMask();
  for (const GraphParameter& prm : params) {
    if (!prm.differentiable()) continue;
    const int i = prm.offset;  // first component
    const double range = prm.max - prm.min;
    double best = 1e30, numBest = 0;
    for (double rel : {1e-3, 2.5e-4}) {
      const double h = rel * range;
      std::vector<float> a = v0, b = v0;
      // one-sided at a bound
      const float lo = std::max(prm.min, static_cast<float>(v0[i] - h)), hi = std::min(prm.max, static_cast<float>(v0[i] + h));
      a[i] = hi;
      b[i] = lo;
      const double num = (lossAt(a, uv0, nullptr, nullptr) - lossAt(b, uv0, nullptr, nullptr)) / (hi - lo);
      if (std::abs(num - dv[i]) < best) best = std::abs(num - dv[i]), numBest = num;
    }
    const double scale = std::max({std::abs(numBest), std::abs(double(dv[i])), 0.05 / range});
    const double err = best / scale;
    std::printf("%-16s analytic %+.5f numeric %+.5f rel %.2e\n", prm.name.c_str(), dv[i], numBest, err);
    worst = std::max(worst, err);
    ++checked;
  }
  for (int k = 0; k < 4; ++k) {
    auto setUv = [&](UvParams u, double d) {
      if (k == 0) u.rotation += d;
      if (k == 1) u.logScale += d;
      if (k == 2) u.offset.x() += d;
      if (k == 3) u.offset.y() += d;
      return u;
    };
    const double ana = k == 0 ? grads.rotation : k == 1 ? grads.logScale : k == 2 ? grads.offset.x() : grads.offset.y();
    double best = 1e30, numBest = 0;
    for (double h : {1e-4, 2.5e-5}) {  // t moves by < 0.03 texel: few bilinear kinks crossed
      const double num = (lossAt(v0, setUv(uv0, h), nullptr, nullptr) - lossAt(v0, setUv(uv0, -h), nullptr, nullptr)) / (2 * h);
      if (std::abs(num - ana) < best) best = std::abs(num - ana), numBest = num;
    }
    const double err = best / std::max({std::abs(numBest), std::abs(ana), 1e-2});
    std::printf("uv[%d]            analytic %+.5f numeric %+.5f rel %.2e\n", k, ana, numBest, err);
    worst = std::max(worst, err);
  }
  *checkedOut = checked;
  return worst;
}

TEST(Optim_PartFit, gradient_through_graph_render_and_loss_matches_finite_differences) {
  int checked = 0;
  const double worst = chainGradientWorst(false, &checked);
  EXPECT_GE(checked, 8);
  EXPECT_LT(worst, 5e-2);
}

// The same chain with the joint texture statistics and the placement term in the loss.
TEST(Optim_PartFit, gradient_with_joint_statistics_and_placement_matches_finite_differences) {
  int checked = 0;
  const double worst = chainGradientWorst(true, &checked);
  EXPECT_GE(checked, 8);
  EXPECT_LT(worst, 5e-2);
}

TEST(Optim_PartFit, new_loss_options_are_validated) {
  std::string err;
  PartFitOptions o = PartFitOptions::preset("balanced");
  EXPECT_TRUE(o.IsValid(&err)) << err;
  EXPECT_GT(o.placementWeight, 0.0f);  // on in balanced by measurement (modules/optim/README.md)
  EXPECT_EQ(PartFitOptions::preset("fast").placementWeight, 0.0f);   // not measured there
  EXPECT_EQ(PartFitOptions::preset("paper").placementWeight, 0.0f);  // the paper's loss
  o.placementWeight = -1.0f;
  EXPECT_FALSE(o.IsValid(&err));
  o = PartFitOptions::preset("balanced");
  o.placementSigma = 0.1f;
  EXPECT_FALSE(o.IsValid(&err));
  o = PartFitOptions::preset("balanced");
  o.psCrossScale = -0.5f;
  EXPECT_FALSE(o.IsValid(&err));
  o = PartFitOptions::preset("balanced");
  o.statWeight = o.textureWeight = 0.0f;
  o.placementWeight = 1.0f;  // the placement term alone is a valid loss
  EXPECT_TRUE(o.IsValid(&err)) << err;
}

// Shared by the recovery test and the scale test: one synthetic part, one fit.
struct Recovery {
  double texDrop = 0, rotDeg = 0, scaleRatio = 0;
  cv::Scalar meanFit, meanTrue;
};

Recovery runRecovery() {
  Recovery out;
  const GraphLibrary lib = GraphLibrary::load();
  MaterialGraph truth = lib.create("wood_planks");
  truth.setValues(truthValues(truth, 21, 0.35f));
  UvParams uvTrue;
  uvTrue.rotation = radians(35.0f);
  uvTrue.logScale = std::log(0.35f);
  uvTrue.offset = Vec2f(0.1f, 0.3f);
  const int W = 160, H = 120;
  Synthetic s = makeSynthetic(truth, uvTrue, W, H, 256, 8, 8);
  const int part = s.room.floor;
  const PartGeometry geo = preparePartGeometry(s.view.gbuffer, s.room.camera.position().cast<float>(), s.view.grid,
                                               s.view.gbuffer.mask[part], part);
  const TextureLossTarget target(s.photo, s.view.gbuffer.mask[part]);
  const MaterialGraph start = lib.create("wood_planks");
  PartFitOptions o = PartFitOptions::preset(std::getenv("PS_FIT_PRESET") ? std::getenv("PS_FIT_PRESET") : "fast");
  o.mapSize = 128;  // the 256 truth's planks and grain survive at 128, not at the preset's 64
  const PartFitResult r = fitPart(start, geo, s.photo, target, o);
  {
    PartFitOptions z = o;
    z.maxIterations = 0;
    const PartFitResult atTruth = fitPart(truth, geo, s.photo, target, z, uvTrue);
    std::printf("loss at the truth: %.4f (texture %.4f)\n", atTruth.initialLoss, atTruth.initialTextureLoss);
    writePng(std::string(PS_BINARY_DIR) + "/part_fit_truth_render.png", atTruth.render);
  }

  MaterialGraph fitted = lib.create("wood_planks");
  fitted.setValues(r.values);
  const MaterialMaps fm = fitted.evaluate(256, MapSet::of({MapKind::Albedo}));
  const cv::Scalar meanFit = cv::mean(fm.albedo), meanTrue = cv::mean(s.truthMaps.albedo);
  double rotDeg = degrees(r.uv.rotation - uvTrue.rotation);
  rotDeg = std::fmod(std::fmod(rotDeg, 180.0) + 270.0, 180.0) - 90.0;  // planks: symmetric under 180 degrees
  const double scaleRatio = std::exp(r.uv.logScale - uvTrue.logScale);
  const double texDrop = 1.0 - r.lossTexture / r.initialTextureLoss;
  std::printf("spectral prior: ok %d, response %.3f, scale ratio %.3f\n", r.spectrum.ok,
              r.spectrum.response, std::exp(r.spectrum.logScale - uvTrue.logScale));
  std::printf("fit: %d it, %d searches (%d candidates), %.2f s; texture loss %.4f -> %.4f (drop %.0f%%)\n",
              r.iterations, r.searches, r.candidates, r.seconds, r.initialTextureLoss, r.lossTexture, 100 * texDrop);
  std::printf("mean albedo fit (%.3f %.3f %.3f) truth (%.3f %.3f %.3f); rotation error %.1f deg; scale ratio %.3f; roughness %.3f\n",
              meanFit[0], meanFit[1], meanFit[2], meanTrue[0], meanTrue[1], meanTrue[2], rotDeg, scaleRatio, r.roughness);
  writePng(std::string(PS_BINARY_DIR) + "/part_fit_photo.png", s.photo);
  writePng(std::string(PS_BINARY_DIR) + "/part_fit_render.png", r.render);
  out.texDrop = texDrop;
  out.rotDeg = rotDeg;
  out.scaleRatio = scaleRatio;
  out.meanFit = meanFit;
  out.meanTrue = meanTrue;
  return out;
}

TEST(Optim_PartFit, recovers_known_material_and_uv_rotation) {
  const Recovery r = runRecovery();
  EXPECT_GE(r.texDrop, 0.8);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.meanFit[c], r.meanTrue[c], 0.03) << "channel " << c;
  EXPECT_LT(std::abs(r.rotDeg), 5.0);
}

// Issue 4's 15% UV-scale target. Without the spectral prior (spectrumScaleWindow = 0) the fit
// lands at 0.700 (`fast`) / 0.692 (`balanced`) with a texture loss below the truth's own: at the
// graph's default parameters the search's best match is the wrong plank width, and the
// parameters then adapt to it. The photo's spectrum against the graph's reads the scale directly.
TEST(Optim_PartFit, on_progress_sees_every_step_and_the_searches_and_stops_the_fit_when_asked) {
  const GraphLibrary lib = GraphLibrary::load();
  MaterialGraph truth = lib.create("wood_planks");
  truth.setValues(truthValues(truth, 5, 0.3f));
  UvParams uv;
  uv.logScale = std::log(0.5f);
  Synthetic s = makeSynthetic(truth, uv, 64, 48, 16, 8, 4);
  const Room& room = s.room;
  const PartGeometry geo =
      preparePartGeometry(s.view.gbuffer, room.camera.position().cast<float>(), s.view.grid,
                          s.view.gbuffer.mask[room.floor], room.floor);
  const TextureLossTarget target(s.photo, s.view.gbuffer.mask[room.floor]);
  struct Case {
    int stopAtStep;     // 0: never
    bool stopInSearch;  // at its report after 64 candidates
  };
  for (const Case c : {Case{0, false}, Case{7, false}, Case{0, true}}) {
    SCOPED_TRACE(testing::Message() << "stop at step " << c.stopAtStep << ", in search " << c.stopInSearch);
    PartFitOptions o = PartFitOptions::preset("fast");
    o.maxIterations = 30;
    o.plateau.minIterations = 1000;  // every step runs unless stopped
    std::vector<PartFitProgress> steps, searches;
    o.onProgress = [&](const PartFitProgress& p) {
      if (p.phase == PartFitProgress::Phase::Search) {
        searches.push_back(p);
        return !(c.stopInSearch && p.candidates >= 64);
      }
      steps.push_back(p);
      return p.iteration != c.stopAtStep;
    };
    const PartFitResult r = fitPart(lib.get("wood_planks"), geo, s.photo, target, o);
    const int expected = c.stopInSearch ? 0 : c.stopAtStep > 0 ? c.stopAtStep : o.maxIterations;
    EXPECT_EQ(r.cancelled, c.stopAtStep > 0 || c.stopInSearch);
    ASSERT_EQ(static_cast<int>(steps.size()), expected);
    EXPECT_EQ(r.iterations, expected);
    ASSERT_EQ(static_cast<int>(r.history.size()), expected);
    for (int i = 0; i < expected; ++i) {
      EXPECT_EQ(steps[i].iteration, i + 1);
      EXPECT_DOUBLE_EQ(steps[i].loss, r.history[i]);  // the step's loss, at its level
      EXPECT_TRUE(std::isfinite(steps[i].loss));
    }
    // the first search runs before the first step; it reports every 64 candidates
    ASSERT_FALSE(searches.empty());
    EXPECT_EQ(searches[0].iteration, 0);
    EXPECT_EQ(searches[0].candidates, 0);
    EXPECT_DOUBLE_EQ(searches[0].loss, r.initialLoss);
    if (c.stopInSearch) {
      // stopped in the first search: the start state, untouched, and no step ran
      EXPECT_EQ(r.candidates, 64);
      EXPECT_EQ(r.values, lib.get("wood_planks").values());
      EXPECT_EQ(r.uv.logScale, 0.0f);
      EXPECT_EQ(r.uv.rotation, 0.0f);
    } else if (c.stopAtStep > 0) {
      // stopped: the fit returns the best state the last report showed, and no finer phase ran
      EXPECT_EQ(r.values, steps.back().values);
      EXPECT_EQ(r.uv.logScale, steps.back().uv.logScale);
      EXPECT_EQ(r.roughness, steps.back().roughness);
      EXPECT_EQ(steps.back().level, r.coarseIterations > 0 ? 1 : 0);
    } else {
      EXPECT_EQ(steps.back().level, 0);  // the last steps at full resolution
      EXPECT_GT(r.candidates, 64);
    }
    EXPECT_TRUE(std::isfinite(r.loss));
  }
}

// heldParameters: a named parameter and every parameter a "prefix*" names stay at their start
// values to the bit, while the others move (selection's short fits hold the octave amplitudes).
TEST(Optim_PartFit, held_parameters_stay_at_their_start) {
  const GraphLibrary lib = GraphLibrary::load();
  MaterialGraph truth = lib.create("wood_planks");
  truth.setValues(truthValues(truth, 5, 0.3f));
  Synthetic s = makeSynthetic(truth, UvParams{}, 64, 48, 16, 8, 4);
  const Room& room = s.room;
  const PartGeometry geo =
      preparePartGeometry(s.view.gbuffer, room.camera.position().cast<float>(), s.view.grid,
                          s.view.gbuffer.mask[room.floor], room.floor);
  const TextureLossTarget target(s.photo, s.view.gbuffer.mask[room.floor]);
  const MaterialGraph& start = lib.get("wood_planks");
  std::vector<std::string> grains;
  for (const GraphParameter& p : start.parameters())
    if (p.name.rfind("grain_", 0) == 0) grains.push_back(p.name);
  ASSERT_FALSE(grains.empty());  // the library's fbm octaves
  PartFitOptions o = PartFitOptions::preset("fast");
  o.maxIterations = 12;
  o.heldParameters = {"grain_*", "wood_light"};
  const PartFitResult r = fitPart(start, geo, s.photo, target, o);
  MaterialGraph fitted = start.clone();
  fitted.setValues(r.values);
  for (const std::string& name : grains)
    EXPECT_EQ(fitted.parameter(name), start.parameter(name)) << name;
  EXPECT_EQ(fitted.parameter("wood_light"), start.parameter("wood_light"));
  int moved = 0;
  for (const GraphParameter& p : start.parameters())
    moved += p.differentiable() && fitted.parameter(p.name) != start.parameter(p.name);
  EXPECT_GE(moved, 3);
}

TEST(Optim_PartFit, recovers_uv_scale_within_15_percent) {
  const Recovery r = runRecovery();
  EXPECT_NEAR(r.scaleRatio, 1.0, 0.15);
}

// scoreMaps evaluates maps that no graph made (a photographed material's) by the fit's loss: given
// a graph's own maps, it must give that graph's score (scorePart) term by term, and the render
// must be the same image.
TEST(Optim_PartFit, scoring_a_graphs_maps_gives_the_graphs_score) {
  const GraphLibrary lib = GraphLibrary::load();
  MaterialGraph truth = lib.create("wood_planks");
  truth.setValues(truthValues(truth, 5, 0.3f));
  UvParams uv;
  uv.rotation = radians(20.0f);
  uv.logScale = std::log(0.5f);
  Synthetic s = makeSynthetic(truth, uv, 80, 60, 16, 8, 2);
  const int part = s.room.floor;
  const PartGeometry geo = preparePartGeometry(
      s.view.gbuffer, s.room.camera.position().cast<float>(), s.view.grid, s.view.gbuffer.mask[part], part);
  const TextureLossTarget target(s.photo, s.view.gbuffer.mask[part]);
  PartFitOptions o = PartFitOptions::preset("balanced");  // placement, prior, highlight, ceiling on
  o.mapSize = 128;
  o.paletteWeight = 0;  // it regularises a graph's values, which maps have not
  PartFitResult state;
  state.values = truth.values();
  state.uv = uv;
  state.uv.offset = Vec2f(0.3f, 0.6f);
  state.roughness = 0.45f;
  const MaterialMaps maps =
      truth.evaluate(o.mapSize, MapSet::of({MapKind::Albedo, MapKind::Normal}));
  for (bool matchMeans : {false, true}) {
    const PartFitResult a = scorePart(truth, state, geo, s.photo, target, o, matchMeans);
    const PartFitResult b = scoreMaps(maps, truth.category(), state.uv, state.roughness, geo,
                                      s.photo, target, o, matchMeans);
    EXPECT_GT(a.loss, 0.0);
    EXPECT_NEAR(b.loss, a.loss, 1e-9 * a.loss);
    EXPECT_NEAR(b.lossStat, a.lossStat, 1e-9 * a.lossStat + 1e-12);
    EXPECT_NEAR(b.lossTexture, a.lossTexture, 1e-9 * a.lossTexture + 1e-12);
    EXPECT_NEAR(b.lossPlacement, a.lossPlacement, 1e-9 + 1e-9 * a.lossPlacement);
    EXPECT_NEAR(b.lossPrior, a.lossPrior, 1e-9 + 1e-9 * a.lossPrior);
    EXPECT_EQ(cv::norm(a.render, b.render, cv::NORM_INF), 0.0);
    // the data terms: the loss less the regularisers, the weighted sum of the photo terms
    EXPECT_NEAR(a.lossData,
                o.statWeight * a.lossStat + o.textureWeight * a.lossTexture +
                    o.placementWeight * a.lossPlacement + o.highlightWeight * a.lossHighlight,
                1e-9 * a.loss);
    EXPECT_GT(a.lossPrior, 0.0);
    EXPECT_LT(a.lossData, a.loss);
  }
  // without the regularisers the data terms are the loss
  PartFitOptions bare = o;
  bare.roughnessPriorWeight = bare.albedoCeilingWeight = 0;
  const PartFitResult c = scorePart(truth, state, geo, s.photo, target, bare);
  EXPECT_NEAR(c.lossData, c.loss, 1e-12);
  // a map that is not square is refused with a message, not read past its end
  MaterialMaps bad = maps;
  bad.albedo = cv::Mat(16, 32, CV_32FC3, cv::Scalar::all(0.5));
  EXPECT_THROW(scoreMaps(bad, "", state.uv, 0.5f, geo, s.photo, target, o), Exception);
}

// The palette prior in the fit (graph/palette_prior.hpp): a start whose wood ramp was pulled
// apart (the dark colour turned green, the light one purple) comes back together with the prior
// and not without it, and the result's loss holds the weighted term, outside lossData.
TEST(Optim_PartFit, the_palette_prior_pulls_a_torn_ramp_back_together) {
  const GraphLibrary lib = GraphLibrary::load();
  MaterialGraph truth = lib.create("wood_planks");
  truth.setValues(truthValues(truth, 5, 0.3f));
  Synthetic s = makeSynthetic(truth, UvParams{}, 64, 48, 16, 8, 2);
  const int part = s.room.floor;
  const PartGeometry geo = preparePartGeometry(s.view.gbuffer, s.room.camera.position().cast<float>(), s.view.grid,
                                               s.view.gbuffer.mask[part], part);
  const TextureLossTarget target(s.photo, s.view.gbuffer.mask[part]);
  MaterialGraph start = lib.create("wood_planks");
  start.setParameter("wood_dark", {0.08f, 0.12f, 0.02f});
  start.setParameter("wood_light", {0.45f, 0.2f, 0.4f});
  const double torn = paletteLoss(start, start.values());
  ASSERT_GT(torn, 1e-3);
  PartFitOptions o = PartFitOptions::preset("fast");
  o.maxIterations = 30;
  o.paletteScope = PaletteScope::Ramps;  // the ramps' prior without a dead zone (the presets
  o.paletteDeadZone = 0.0f;              // hold all the colours, past the draws' spread)
  o.paletteWeight = 0.0f;
  const PartFitResult without = fitPart(start, geo, s.photo, target, o);
  o.paletteWeight = 30.0f;
  const PartFitResult with = fitPart(start, geo, s.photo, target, o);
  MaterialGraph g = lib.create("wood_planks");
  const double lWithout = paletteLoss(g, without.values), lWith = paletteLoss(g, with.values);
  std::printf("palette loss: start %.4f, fitted without the prior %.4f, with %.4f\n", torn, lWithout, lWith);
  EXPECT_LT(lWith, 0.5 * torn);
  EXPECT_LT(lWith, 0.5 * lWithout);
  EXPECT_EQ(without.lossPalette, 0.0);
  EXPECT_NEAR(with.lossPalette, lWith, 1e-9);
  // a regulariser: in the loss, not in the data terms (the other regularisers are >= 0)
  EXPECT_GE(with.loss - with.lossData, o.paletteWeight * with.lossPalette - 1e-9);
  EXPECT_GT(with.lossPalette, 0.0);
}

}  // namespace
}  // namespace ps
