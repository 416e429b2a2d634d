#include "photoscene/optim/part_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <optional>

#include "photoscene/core/log.hpp"

#include "photoscene/core/error.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/features/texture_placement.hpp"
#include "photoscene/graph/palette_prior.hpp"
#include "photoscene/core/color.hpp"

namespace ps {

PartFitOptions PartFitOptions::preset(const std::string& name) {
  PartFitOptions o;
  if (name == "paper") {
    o.maxIterations = 1000;
    o.mapSize = 256;
    o.uvSearchEvery = 50;
    o.searchRotations = 72;
    o.searchLogScales = 32;
    o.searchOffsets = 5;
    o.refineSteps = 0;
    o.specularSub = 2;
    o.searchSpecularSub = 2;
    o.plateau = PlateauOptions{50, 1e-4, 200};
    o.restarts = 0;
    // every Adam step at full resolution, as the paper; the 57,600 search candidates are ranked at
    // half resolution and the best 16 compared again at full resolution (else a search takes
    // about 10 minutes per part on one core)
    o.coarseLevels = 0;
    o.searchLevels = 1;
    o.searchKeep = 16;
    o.spectrumScaleWindow = 0.0f;  // the paper's whole scale grid, no spectral prior
  } else if (name == "balanced" || name == "fast") {
    // both: the search's ranking at half resolution (coarseLevels 1, searchLevels 2), one search
    // at the start, two refining steps, and the terms that keep roughness and albedo plausible
    o.mapSize = 128;  // fast: at 64 the checker's tiles alias and the search picks a wrong period
    o.uvSearchEvery = 0;  // balanced: a second search at 100 cost 40% more, changed no result
    o.searchLogScales = 9;
    o.searchOffsets = 1;
    o.refineSteps = 2;
    o.coarseLevels = 1;
    o.searchLevels = 2;
    o.roughnessPriorWeight = 0.01f;
    o.roughnessCandidates = 9;
    o.highlightWeight = 0.1f;
    o.albedoCeilingWeight = 0.1f;
    // the spectral shape (how the band energy spreads over scale and orientation): closer to the
    // truth on our own graphs and on the real-texture yardstick; at 1 the own graphs' rotation
    // drifted (modules/optim/README.md)
    o.bandShape = 0.3f;
    if (name == "balanced") {
      // chosen with ps_bench_part_fit (modules/optim/README.md): 20 steps at half resolution,
      // the last 20 at full resolution. Against the truth (4 graphs x 2 lightings at 21k pixels)
      // 40 steps reached a lower texture distance than 100 (0.00102 against 0.00140; mean albedo
      // error 0.014 against 0.013) in 77 % of the time.
      o.maxIterations = 40;
      o.searchRotations = 24;
      o.searchKeep = 8;
      o.fineIterations = 20;
      o.plateau = PlateauOptions{20, 2e-3, 60};
      // the placement term (modules/optim/README.md): wood_planks, tile_checker, brick_red x
      // lights 12 and 30 at 160x120, against 0: placement to the truth 0.299 -> 0.046 (mean),
      // texture distance to the truth 0.00105 -> 0.00077, mean albedo error 0.0100 -> 0.0115,
      // CPU +35 %
      o.placementWeight = 0.1f;
    } else {
      // 30 steps, 10 at full resolution: against the truth at 21k pixels a texture distance of
      // 0.0036 (80 steps gave 0.0064 on wood and the checker) in 69 % of balanced's time
      o.maxIterations = 30;
      o.searchRotations = 16;
      o.searchKeep = 4;
      o.fineIterations = 10;
      o.learningRate = 0.03f;
      o.plateau = PlateauOptions{15, 3e-3, 40};
    }
  } else {
    PS_Check(false, "PartFitOptions::preset: unknown preset '" + name + "' (paper, balanced, fast)");
  }
  return o;
}

bool PartFitOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  if (maxIterations < 0) return fail("maxIterations must be >= 0");
  if (mapSize < 4 || (mapSize & (mapSize - 1))) return fail("mapSize must be a power of two >= 4");
  if (!(learningRate > 0) || !(uvLearningRate >= 0)) return fail("learning rates must be positive");
  if (!(statWeight >= 0) || !(textureWeight >= 0) || !(placementWeight >= 0) ||
      statWeight + textureWeight + placementWeight <= 0)
    return fail("loss weights must be >= 0, not all 0");
  if (!(placementSigma >= 0.5f && placementSigma <= 32.0f)) return fail("placementSigma must be in [0.5, 32]");
  if (placementOffsets < 0) return fail("placementOffsets must be >= 0");
  if (!(psAutoLowpass >= 0) || !(psAutoMagnitude >= 0) || !(psCrossOrientation >= 0) || !(psCrossScale >= 0) ||
      !(psColor >= 0) || !(colorSliced >= 0) || !(bandShape >= 0))
    return fail("the ps*, colorSliced and bandShape texture weights must be >= 0");
  if (searchRotations < 1 || searchLogScales < 1 || searchOffsets < 1) return fail("search grids need >= 1 entry");
  if (!(spectrumScaleWindow >= 0)) return fail("spectrumScaleWindow must be >= 0");
  if (!(logScaleMax >= logScaleMin)) return fail("logScaleMax < logScaleMin");
  if (specularSub < 1 || specularSub > 8 || searchSpecularSub < 1 || searchSpecularSub > 8)
    return fail("specularSub must be in [1, 8]");
  if (!(lobeFilter >= 0 && lobeFilter <= 4)) return fail("lobeFilter must be in [0, 4]");
  if (restarts < 0 || restartProbeIterations < 1) return fail("bad restart settings");
  if (coarseLevels < 0 || coarseLevels > 4 || searchLevels < 0 || searchLevels > 4)
    return fail("coarseLevels and searchLevels must be in [0, 4]");
  if (fineIterations < 0 || minLevelPixels < 1 || searchKeep < 1)
    return fail("fineIterations must be >= 0, minLevelPixels and searchKeep >= 1");
  if (!(fineLearningRateScale > 0)) return fail("fineLearningRateScale must be > 0");
  if (!(roughnessPriorWeight >= 0) || !(highlightWeight >= 0) || !(albedoCeilingWeight >= 0))
    return fail("roughnessPriorWeight, highlightWeight and albedoCeilingWeight must be >= 0");
  if (!(albedoCeilingKnee > 0.5f && albedoCeilingKnee < 1.0f))
    return fail("albedoCeilingKnee must be in (0.5, 1)");
  if (!(paletteWeight >= 0)) return fail("paletteWeight must be >= 0");
  if (!(paletteDeadZone >= 0)) return fail("paletteDeadZone must be >= 0");
  if (!(highlight.glossyRoughness > 0.01f && highlight.glossyRoughness <= 1.0f) ||
      !(highlight.minRatio > 0) || highlight.minPixels < 1 ||
      !(highlight.maxFraction > highlight.minFraction))
    return fail("highlight options out of range");
  if (!plateau.IsValid(error)) return false;
  return true;
}

double statLoss(const cv::Mat& photo, const cv::Mat& render, const std::vector<cv::Point>& pixels, cv::Mat* grad,
                const cv::Vec3d& photoNoise) {
  PS_Check(photo.type() == CV_32FC3 && render.type() == CV_32FC3 && photo.size() == render.size(),
           "statLoss: photo and render must be CV_32FC3 of one size");
  if (grad) {
    grad->create(render.size(), CV_32FC3);
    grad->setTo(cv::Scalar::all(0));
  }
  const double n = static_cast<double>(pixels.size());
  if (n == 0) return 0.0;
  double mp[3] = {0, 0, 0}, mr[3] = {0, 0, 0}, vp[3] = {0, 0, 0}, vr[3] = {0, 0, 0};
  for (const cv::Point& p : pixels) {
    const cv::Vec3f a = photo.at<cv::Vec3f>(p), b = render.at<cv::Vec3f>(p);
    for (int c = 0; c < 3; ++c) mp[c] += a[c], mr[c] += b[c];
  }
  for (int c = 0; c < 3; ++c) mp[c] /= n, mr[c] /= n;
  for (const cv::Point& p : pixels) {
    const cv::Vec3f a = photo.at<cv::Vec3f>(p), b = render.at<cv::Vec3f>(p);
    for (int c = 0; c < 3; ++c) vp[c] += (a[c] - mp[c]) * (a[c] - mp[c]), vr[c] += (b[c] - mr[c]) * (b[c] - mr[c]);
  }
  for (int c = 0; c < 3; ++c) vp[c] = std::max(0.0, vp[c] / n - photoNoise[c] * photoNoise[c]), vr[c] /= n;
  const double nu = std::max(1e-3, luminance(mp[0], mp[1], mp[2]));
  double loss = 0;
  double sMean[3], sVar[3];
  for (int c = 0; c < 3; ++c) {
    loss += std::abs(mr[c] - mp[c]) / nu + std::abs(vr[c] - vp[c]) / (nu * nu);
    sMean[c] = (mr[c] > mp[c] ? 1.0 : mr[c] < mp[c] ? -1.0 : 0.0) / (nu * n);
    sVar[c] = (vr[c] > vp[c] ? 1.0 : vr[c] < vp[c] ? -1.0 : 0.0) / (nu * nu * n);
  }
  if (grad)
    for (const cv::Point& p : pixels) {
      const cv::Vec3f b = render.at<cv::Vec3f>(p);
      cv::Vec3f& g = grad->at<cv::Vec3f>(p);
      for (int c = 0; c < 3; ++c) g[c] = static_cast<float>(sMean[c] + sVar[c] * 2.0 * (b[c] - mr[c]));
    }
  return loss;
}

namespace {

constexpr double kTwoPi = 6.283185307179586;

struct FitState {
  std::vector<float> values;  // graph values (raw)
  float roughness = 0.5f;
  UvParams uv;
};

// The part at one resolution: level 0 is the caller's, level i + 1 halves level i.
struct Level {
  const PartGeometry* geo = nullptr;
  cv::Mat photo;
  const TextureLossTarget* target = nullptr;
  std::unique_ptr<PartGeometry> ownGeo;
  std::unique_ptr<TextureLossTarget> ownTarget;
  std::unique_ptr<PlacementLossTarget> placement;  // when placementWeight > 0
  std::vector<cv::Point> highlight;                // when highlightWeight > 0 (may be empty)
};

// Weights of the texture loss that the fit sets itself (its own targets then).
bool ownTextureWeights(const PartFitOptions& o) {
  return o.psAutoLowpass > 0 || o.psAutoMagnitude > 0 || o.psCrossOrientation > 0 || o.psCrossScale > 0 ||
         o.psColor > 0 || o.colorSliced > 0 || o.bandShape > 0;
}

// The texture-loss options the fit uses: the caller's, with the fit's joint-statistics, colour
// distribution and spectral shape weights.
TextureLossOptions fitTextureOptions(const TextureLossOptions& caller, const PartFitOptions& o) {
  TextureLossOptions t = caller;
  if (ownTextureWeights(o)) {
    t.weights.psAutoLowpass = o.psAutoLowpass;
    t.weights.psAutoMagnitude = o.psAutoMagnitude;
    t.weights.psCrossOrientation = o.psCrossOrientation;
    t.weights.psCrossScale = o.psCrossScale;
    t.weights.psColor = o.psColor;
    t.weights.colorSliced = o.colorSliced;
    t.weights.bandShape = o.bandShape;
  }
  return t;
}

cv::Mat maskOf(const PartGeometry& geo) {
  cv::Mat m = cv::Mat::zeros(geo.imageSize, CV_8UC1);
  for (const cv::Point& q : geo.pixels) m.at<uint8_t>(q) = 255;
  return m;
}

class PartFitter {
 public:
  // `g` null: a fitter that only evaluates given maps (scoreMaps); the prior's category is then
  // o.roughnessCategory's.
  PartFitter(const MaterialGraph* g, const PartGeometry& geo, const cv::Mat& photo, const TextureLossTarget& target,
             const PartFitOptions& o)
      : o_(o) {
    if (g) graph_.emplace(g->clone());
    levels_.emplace_back();
    levels_[0].geo = &geo;
    levels_[0].photo = photo;
    levels_[0].target = &target;
    const TextureLossOptions texOptions = fitTextureOptions(target.options(), o);
    if (ownTextureWeights(o) || o.placementWeight > 0) {
      const cv::Mat mask0 = maskOf(geo);
      if (ownTextureWeights(o)) {
        levels_[0].ownTarget = std::make_unique<TextureLossTarget>(photo, mask0, texOptions);
        levels_[0].target = levels_[0].ownTarget.get();
      }
      if (o.placementWeight > 0)
        levels_[0].placement = std::make_unique<PlacementLossTarget>(
            photo, mask0, PlacementLossOptions{static_cast<double>(o.placementSigma)});
    }
    const int want = std::max(o.coarseLevels, o.searchLevels);
    while (static_cast<int>(levels_.size()) <= want) {
      const Level& f = levels_.back();
      cv::Mat mask;
      auto cg = std::make_unique<PartGeometry>(downsamplePartGeometry(*f.geo, &mask));
      if (cg->size() < o.minLevelPixels) break;
      Level c;
      c.photo = downsampleImage(*cg, f.photo);
      c.ownTarget = std::make_unique<TextureLossTarget>(c.photo, mask, texOptions);
      c.target = c.ownTarget.get();
      if (o.placementWeight > 0) {
        const double sigma = std::max(0.5, o.placementSigma / std::ldexp(1.0, static_cast<int>(levels_.size())));
        c.placement = std::make_unique<PlacementLossTarget>(c.photo, mask, PlacementLossOptions{sigma});
      }
      c.ownGeo = std::move(cg);
      c.geo = c.ownGeo.get();
      levels_.push_back(std::move(c));
    }
    if (o.highlightWeight > 0)
      for (Level& lv : levels_) lv.highlight = highlightRegion(*lv.geo, o.highlight);
    prior_ = roughnessPriorFor(o.roughnessCategory.empty() && graph_ ? graph_->category()
                                                                     : o.roughnessCategory);
    coarseLevel_ = std::min(o.coarseLevels, static_cast<int>(levels_.size()) - 1);
    searchLevel_ = std::min(o.searchLevels, static_cast<int>(levels_.size()) - 1);
    if (!graph_) return;
    const auto& params = graph_->parameters();
    const int n = graph_->valueCount();
    lo_.assign(n, 0.0f);
    hi_.assign(n, 1.0f);
    for (const GraphParameter& p : params)
      for (int k = 0; k < p.dim; ++k) {
        lo_[p.offset + k] = p.min;
        hi_[p.offset + k] = p.max;
      }
    mask_ = graph_->differentiableMask();
    for (const GraphParameter& p : params)
      if (isHeld(p.name, o.heldParameters))
        std::fill_n(mask_.begin() + p.offset, p.dim, uint8_t(0));
  }

  static bool isHeld(const std::string& name, const std::vector<std::string>& held) {
    for (const std::string& h : held) {
      const bool prefix = !h.empty() && h.back() == '*';
      if (prefix ? name.compare(0, h.size() - 1, h, 0, h.size() - 1) == 0 : name == h) return true;
    }
    return false;
  }

  using Eval = PartFitLosses;

  // Loss of the current maps under (uv, roughness); with grads, also the layer's gradients.
  Eval evaluate(int level, const MaterialMaps& maps, const UvParams& uv, float roughness, int sub,
                RenderLayerGradients* grads, cv::Mat* renderOut = nullptr, bool matchMeans = false) {
    const Level& lv = levels_[level];
    const PartGeometry& geo = *lv.geo;
    const cv::Mat& photo = lv.photo;
    const TextureLossTarget& target = *lv.target;
    RenderLayerParams p;
    p.geometry = &geo;
    p.albedo = maps.albedo;
    p.normal = maps.normal;
    p.roughnessValue = roughness;
    p.uv = uv;
    p.specularSub = sub;
    p.lobeFilter = o_.lobeFilter;
    renderLayerForward(p);
    if (matchMeans) {
      // the search compares patterns, not colours: the render's masked channel means are scaled to
      // the photo's first (the continuous fit then moves the colours)
      double mr[3] = {0, 0, 0}, mp[3] = {0, 0, 0};
      for (const cv::Point& q : geo.pixels) {
        const cv::Vec3f a = p.image.at<cv::Vec3f>(q), b = photo.at<cv::Vec3f>(q);
        for (int c = 0; c < 3; ++c) mr[c] += a[c], mp[c] += b[c];
      }
      const cv::Scalar gain(mr[0] > 1e-9 ? mp[0] / mr[0] : 1.0, mr[1] > 1e-9 ? mp[1] / mr[1] : 1.0,
                            mr[2] > 1e-9 ? mp[2] / mr[2] : 1.0);
      cv::multiply(p.image, gain, p.image);
    }
    Eval e;
    cv::Mat gImage;  // d loss / d render image
    if (o_.statWeight > 0) {
      cv::Mat g;
      e.lossStat = statLoss(photo, p.image, geo.pixels, grads ? &g : nullptr, target.photoNoise());
      if (grads) gImage = g * o_.statWeight;
    }
    if (o_.textureWeight > 0) {
      TextureLossParams tp;
      tp.target = &target;
      tp.render = p.image;
      e.lossTexture = textureLossForward(tp);
      if (grads) textureLossBackward(tp, o_.textureWeight, gImage, !gImage.empty());
    }
    if (o_.placementWeight > 0)
      e.lossPlacement = placementLoss(*lv.placement, p.image, grads ? &gImage : nullptr, o_.placementWeight, !gImage.empty());
    if (o_.highlightWeight > 0 && !lv.highlight.empty())
      e.lossHighlight = highlightLoss(photo, p.image, geo.pixels, lv.highlight,
                                  grads ? &gImage : nullptr, o_.highlightWeight);
    if (gImage.empty() && grads) gImage = cv::Mat::zeros(p.image.size(), CV_32FC3);
    double gPrior = 0;
    if (o_.roughnessPriorWeight > 0) e.lossPrior = roughnessPriorLoss(prior_, roughness, &gPrior);
    const double priorWeight =
        o_.roughnessPriorWeight * (hasHighlight() ? 1.0 : o_.noHighlightPriorScale);
    cv::Mat gCeil;
    if (o_.albedoCeilingWeight > 0)
      e.lossCeiling = albedoCeilingLoss(maps.albedo, o_.albedoCeilingKnee, grads ? &gCeil : nullptr,
                                    o_.albedoCeilingWeight);
    e.lossData = o_.statWeight * e.lossStat + o_.textureWeight * e.lossTexture +
                 o_.placementWeight * e.lossPlacement + o_.highlightWeight * e.lossHighlight;
    e.loss = e.lossData + priorWeight * e.lossPrior + o_.albedoCeilingWeight * e.lossCeiling;
    if (grads) {
      renderLayerBackward(p, gImage, *grads);
      grads->roughnessValue += static_cast<float>(priorWeight * gPrior);
      if (!gCeil.empty()) grads->albedo += gCeil;
    }
    if (renderOut) *renderOut = p.image;
    return e;
  }

  // L_palette at `values` (graph/palette_prior.hpp) added to e's loss as a regulariser (not to
  // lossData); with `grad`, its weighted gradient with respect to the values.
  void addPalette(Eval& e, const std::vector<float>& values, std::vector<float>* grad = nullptr) {
    if (!graph_ || o_.paletteWeight <= 0) return;
    e.lossPalette = paletteLoss(*graph_, values, grad, o_.paletteScope, o_.paletteDeadZone);
    e.loss += o_.paletteWeight * e.lossPalette;
    if (grad)
      for (float& g : *grad) g *= o_.paletteWeight;
  }

  MaterialMaps maps(const std::vector<float>& values) {
    graph_->setValues(values);
    return graph_->evaluate(o_.mapSize, MapSet::of({MapKind::Albedo, MapKind::Normal}));
  }

  float meanRoughness(const std::vector<float>& values) {
    graph_->setValues(values);
    const MaterialMaps m = graph_->evaluate(o_.mapSize, MapSet::of({MapKind::Roughness}));
    return m.roughness.empty() ? 0.5f : static_cast<float>(cv::mean(m.roughness)[0]);
  }

  // Discrete UV search with the maps of `values`; returns the best transform and its loss.
  // Discrete UV search with the maps of `values`; returns the best transform and its loss. With a
  // coarse search level, the grid is ranked there and its `searchKeep` best (and the current
  // transform) are compared again at full resolution, where the refinement runs.
  UvParams search(const FitState& s, double* bestLoss, int* candidates) {
    const MaterialMaps m = maps(s.values);
    auto loss = [&](int level, const UvParams& uv) {
      if (cancelled_) return std::numeric_limits<double>::infinity();
      if (o_.onProgress && *candidates % 64 == 0) {
        PartFitProgress pr;
        pr.phase = PartFitProgress::Phase::Search;
        pr.iteration = iterations_;
        pr.candidates = *candidates;
        pr.level = level;
        pr.loss = stateLoss_;
        pr.values = s.values;
        pr.uv = s.uv;
        pr.roughness = s.roughness;
        if (!o_.onProgress(pr)) {
          cancelled_ = true;
          return std::numeric_limits<double>::infinity();
        }
      }
      ++*candidates;
      return evaluate(level, m, uv, s.roughness, o_.searchSpecularSub, nullptr, nullptr, true).loss;
    };
    const double rotStep = kTwoPi / o_.searchRotations;
    // log-scales: the whole range, or three around the spectral prior's estimate
    const bool prior = spectrum_.ok && o_.spectrumScaleWindow > 0;
    const int nScales = prior ? 3 : o_.searchLogScales;
    const double lsStep = prior ? o_.spectrumScaleWindow
                          : o_.searchLogScales > 1
                              ? (o_.logScaleMax - o_.logScaleMin) / (o_.searchLogScales - 1)
                              : 0.0;
    const double ls0 = prior ? spectrum_.logScale - lsStep : o_.logScaleMin;
    std::vector<std::pair<double, UvParams>> grid;
    for (int i = 0; i < o_.searchRotations; ++i)
      for (int j = 0; j < nScales; ++j)
        for (int a = 0; a < o_.searchOffsets; ++a)
          for (int b = 0; b < o_.searchOffsets; ++b) {
            UvParams uv;
            uv.rotation = static_cast<float>(i * rotStep);
            uv.logScale = nScales > 1 ? static_cast<float>(ls0 + j * lsStep) : s.uv.logScale;
            uv.offset = o_.searchOffsets > 1 ? Vec2f(float(a) / o_.searchOffsets, float(b) / o_.searchOffsets) : s.uv.offset;
            grid.emplace_back(loss(searchLevel_, uv), uv);
          }
    if (prior)  // the spectrum's rotation (known modulo 180 degrees; tiles repeat every 90) at each scale
      for (int k = 0; k < 4; ++k)
        for (int j = 0; j < nScales; ++j) {
          UvParams uv = s.uv;
          uv.rotation = static_cast<float>(spectrum_.rotation + k * kTwoPi / 4);
          uv.logScale = static_cast<float>(ls0 + j * lsStep);
          grid.emplace_back(loss(searchLevel_, uv), uv);
        }
    UvParams best = s.uv;
    double bl = loss(0, s.uv);
    auto tryUv = [&](const UvParams& uv) {
      const double l = loss(0, uv);
      if (l < bl) bl = l, best = uv;
    };
    if (searchLevel_ == 0) {
      for (const auto& [l, uv] : grid)
        if (l < bl) bl = l, best = uv;
    } else {
      const size_t keep = std::min(grid.size(), static_cast<size_t>(o_.searchKeep));
      std::partial_sort(grid.begin(), grid.begin() + keep, grid.end(),
                        [](const auto& x, const auto& y) { return x.first < y.first; });
      for (size_t i = 0; i < keep; ++i) tryUv(grid[i].second);
    }
    // coarse to fine: halve the steps around the best
    double rs = rotStep, ls = lsStep;
    for (int r = 0; r < o_.refineSteps; ++r) {
      rs *= 0.5;
      ls *= 0.5;
      const UvParams c = best;
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj) {
          if (di == 0 && dj == 0) continue;
          UvParams uv = c;
          uv.rotation = static_cast<float>(c.rotation + di * rs);
          uv.logScale = static_cast<float>(c.logScale + dj * ls);
          tryUv(uv);
        }
    }
    // the placement term sees the offset: a low-discrepancy set of offsets (the R2 sequence) around
    // the best, so a pattern of any period in uv gets candidates at several of its phases
    if (o_.placementWeight > 0) {
      const UvParams c = best;
      auto frac = [](double v) { return v - std::floor(v); };
      for (int i = 1; i <= o_.placementOffsets; ++i) {
        UvParams uv = c;
        uv.offset = Vec2f(static_cast<float>(frac(c.offset.x() + i * 0.7548776662466927)),
                          static_cast<float>(frac(c.offset.y() + i * 0.5698402909980532)));
        tryUv(uv);
      }
    }
    *bestLoss = bl;
    return cancelled_ ? s.uv : best;
  }

  // Runs up to `iterations` Adam steps from `s` (search first when `searchFirst`); returns the
  // best state seen and its loss.
  double run(FitState& s, int iterations, bool searchFirst, bool searchAgain, int level, PartFitResult& res,
             bool record, float learningRateScale = 1.0f) {
    const int n = graph_->valueCount();
    const int N = n + 5;
    std::vector<float> x(N), lower(N), upper(N), scales(N, 1.0f);
    std::vector<uint8_t> mask(N, 1);
    auto pack = [&](const FitState& st) {
      for (int i = 0; i < n; ++i) {
        const float r = hi_[i] - lo_[i];
        x[i] = r > 0 ? (st.values[i] - lo_[i]) / r : 0.0f;
        lower[i] = 0, upper[i] = 1;
        mask[i] = mask_[i] && r > 0;
      }
      x[n] = st.roughness;
      lower[n] = roughnessMin(), upper[n] = roughnessMax();
      x[n + 1] = st.uv.rotation, x[n + 2] = st.uv.logScale, x[n + 3] = st.uv.offset.x(), x[n + 4] = st.uv.offset.y();
      for (int k = 1; k <= 4; ++k) {
        lower[n + k] = -1e4f, upper[n + k] = 1e4f;
        scales[n + k] = o_.uvLearningRate / o_.learningRate;
        mask[n + k] = o_.fitUvContinuous ? 1 : 0;
      }
      lower[n + 2] = o_.logScaleMin - 1.0f, upper[n + 2] = o_.logScaleMax + 1.0f;
      if (spectrum_.ok && o_.spectrumScaleWindow > 0) {  // the spectral prior bounds the scale
        lower[n + 2] = spectrum_.logScale - o_.spectrumScaleWindow;
        upper[n + 2] = spectrum_.logScale + o_.spectrumScaleWindow;
      }
    };
    auto unpack = [&](FitState& st) {
      std::vector<float> v(n);
      for (int i = 0; i < n; ++i) v[i] = mask[i] ? lo_[i] + x[i] * (hi_[i] - lo_[i]) : st.values[i];
      st.values = graph_->projectValues(v);
      st.roughness = x[n];
      st.uv.rotation = x[n + 1], st.uv.logScale = x[n + 2], st.uv.offset = Vec2f(x[n + 3], x[n + 4]);
    };
    pack(s);
    Adam adam(N, AdamOptions{o_.learningRate * learningRateScale});
    adam.setBounds(lower, upper);
    adam.setMask(mask);
    adam.setScales(scales);
    PlateauDetector plateau(o_.plateau);
    FitState best = s;
    double bestLoss = std::numeric_limits<double>::infinity();
    for (int it = 0; it < iterations; ++it) {
      const bool doSearch =
          (it == 0 && searchFirst) || (searchAgain && o_.uvSearchEvery > 0 && it > 0 && it % o_.uvSearchEvery == 0);
      if (doSearch) {
        double sl = 0;
        const Timer st;
        iterations_ = res.iterations;
        const UvParams uv = search(s, &sl, &res.candidates);
        res.searchSeconds += st.seconds();
        ++res.searches;
        if (cancelled_) {
          res.cancelled = true;
          break;
        }
        if (uv.rotation != s.uv.rotation || uv.logScale != s.uv.logScale || uv.offset != s.uv.offset) {
          s.uv = uv;
          pack(s);
          adam.reset();
        }
      }
      const MaterialMaps m = maps(s.values);
      RenderLayerGradients g;
      Eval e = evaluate(level, m, s.uv, s.roughness, o_.specularSub, &g);
      std::vector<float> gPalette;
      addPalette(e, s.values, &gPalette);
      stateLoss_ = e.loss;
      if (record) res.history.push_back(e.loss);
      if (e.loss < bestLoss) bestLoss = e.loss, best = s;
      if (plateau.update(e.loss)) {
        res.stoppedOnPlateau = true;
        break;
      }
      MaterialMaps dm;
      dm.albedo = g.albedo;
      dm.normal = g.normal;
      const std::vector<float> dv = graph_->backward(dm);
      std::vector<float> grad(N, 0.0f);
      for (int i = 0; i < n; ++i) grad[i] = (dv[i] + (gPalette.empty() ? 0.0f : gPalette[i])) * (hi_[i] - lo_[i]);
      grad[n] = g.roughnessValue;
      grad[n + 1] = g.rotation, grad[n + 2] = g.logScale, grad[n + 3] = g.offset.x(), grad[n + 4] = g.offset.y();
      adam.step(x, grad);
      unpack(s);
      ++res.iterations;
      if (o_.onProgress) {
        PartFitProgress pr;
        pr.iteration = res.iterations;
        pr.candidates = res.candidates;
        pr.level = level;
        pr.loss = e.loss;
        pr.values = best.values;
        pr.uv = best.uv;
        pr.roughness = best.roughness;
        if (!o_.onProgress(pr)) {
          res.cancelled = true;
          break;
        }
      }
    }
    s = best;
    return bestLoss;
  }

  // A line search over the held roughness with the state's maps and UV transform: `n` values
  // log-spaced over the allowed range, and the current one; the state takes the best. Adam alone
  // moves one scalar slowly and stops where the data term is flat.
  void searchRoughness(FitState& s, int level, int n, PartFitResult& res) {
    if (n < 2) return;
    const MaterialMaps m = maps(s.values);
    // the render's channel means are matched to the photo's (as in the UV search): the albedo was
    // fitted under the current roughness, and the mean term would hold the roughness where it is
    double best =
        evaluate(level, m, s.uv, s.roughness, o_.specularSub, nullptr, nullptr, true).loss;
    const float lo = roughnessMin(), hi = roughnessMax();
    const bool debug = std::getenv("PS_DEBUG_ROUGHNESS") != nullptr;
    for (int i = 0; i < n; ++i) {
      const float r = lo * std::pow(hi / lo, static_cast<float>(i) / (n - 1));
      const double l = evaluate(level, m, s.uv, r, o_.specularSub, nullptr, nullptr, true).loss;
      if (debug) std::fprintf(stderr, "roughness search: r %.3f loss %.5f\n", r, l);
      ++res.candidates;
      if (l < best) best = l, s.roughness = r;
    }
    if (debug) std::fprintf(stderr, "roughness search: picked %.3f\n", s.roughness);
  }

  int coarseLevel() const { return coarseLevel_; }
  float roughnessMin() const {
    return o_.roughnessPriorWeight > 0 ? std::max(0.02f, prior_.min) : 0.02f;
  }
  float roughnessMax() const {
    return o_.roughnessPriorWeight > 0 ? std::min(1.0f, prior_.max) : 1.0f;
  }
  const RoughnessPrior& prior() const { return prior_; }
  // the light predicts a highlight on the part (at full resolution): only then can the photo say
  // how glossy it is
  bool hasHighlight() const { return o_.highlightWeight > 0 && !levels_[0].highlight.empty(); }
  int highlightPixels() const { return static_cast<int>(levels_[0].highlight.size()); }

  // The spectral prior: the photo's spectrum against the albedo of `values` (see uv_spectrum.hpp).
  UvSpectrumEstimate estimateSpectrum(const std::vector<float>& values) {
    graph_->setValues(values);
    // at 256 at least: at 128 the grain's 36 rings a period blur and wood's estimate was 22 % off
    const MaterialMaps m =
        graph_->evaluate(std::max(o_.mapSize, 256), MapSet::of({MapKind::Albedo}));
    cv::Mat lum(m.albedo.size(), CV_32F);
    for (int y = 0; y < lum.rows; ++y)
      for (int x = 0; x < lum.cols; ++x) {
        const cv::Vec3f c = m.albedo.at<cv::Vec3f>(y, x);
        lum.at<float>(y, x) = luminance(c);
      }
    // the lighting, to divide out of the photo: the layer's render of a white diffuse material
    RenderLayerParams p;
    p.geometry = levels_[0].geo;
    p.albedo = cv::Mat(4, 4, CV_32FC3, cv::Scalar::all(1.0));
    p.specular = 0.0f;
    p.specularSub = 1;
    renderLayerForward(p);
    spectrum_ = estimateUvBySpectrum(*levels_[0].geo, levels_[0].photo, p.image, lum);
    return spectrum_;
  }

  std::optional<MaterialGraph> graph_;  // absent: maps are given (scoreMaps)
  PartFitOptions o_;
  std::vector<Level> levels_;
  int coarseLevel_ = 0, searchLevel_ = 0;
  std::vector<float> lo_, hi_;
  std::vector<uint8_t> mask_;
  UvSpectrumEstimate spectrum_;
  RoughnessPrior prior_;
  bool cancelled_ = false;  // onProgress returned false
  int iterations_ = 0;      // Adam steps before the running search (for its progress reports)
  double stateLoss_ = 0;    // the last evaluated state's loss (for search progress reports)
};


}  // namespace

PartFitResult fitPart(const MaterialGraph& graph, const PartGeometry& geometry, const cv::Mat& photo,
                      const TextureLossTarget& target, const PartFitOptions& options, const UvParams& initialUv) {
  std::string err;
  PS_Check(options.IsValid(&err), "fitPart: invalid options: " + err);
  PS_Check(photo.type() == CV_32FC3 && photo.size() == geometry.imageSize, "fitPart: photo must be CV_32FC3 of the geometry's size");
  PS_Check(target.imageSize() == geometry.imageSize, "fitPart: texture-loss target and geometry sizes differ");
  PS_Check(geometry.size() > 0, "fitPart: the part has no pixels");
  Timer timer;
  PartFitter f(&graph, geometry, photo, target, options);
  PartFitResult res;
  FitState start;
  start.values = graph.values();
  start.uv = initialUv;
  const float meanR = f.meanRoughness(start.values);
  start.roughness = clampv(meanR, f.roughnessMin(), f.roughnessMax());
  if (options.roughnessPriorWeight > 0) res.roughnessPrior = f.prior();
  res.highlightPixels = f.highlightPixels();
  {
    PartFitter::Eval e0 = f.evaluate(0, f.maps(start.values), start.uv, start.roughness, options.specularSub, nullptr);
    f.addPalette(e0, start.values);
    res.initialLoss = e0.loss;
    f.stateLoss_ = e0.loss;
    res.initialTextureLoss = e0.lossTexture;
  }
  if (options.spectrumScaleWindow > 0) {
    const Timer st;
    res.spectrum = f.estimateSpectrum(start.values);
    res.spectrumSeconds = st.seconds();
    res.searchSeconds += res.spectrumSeconds;
  }
  FitState s = start;
  int remaining = options.maxIterations;
  const int coarse = f.coarseLevel();
  if (options.restarts > 0 && options.maxIterations > options.restartProbeIterations) {
    // probes: the start and `restarts` random draws, each a short run; the best is continued
    double bestProbe = std::numeric_limits<double>::infinity();
    FitState bestState = start;
    for (int r = 0; r <= options.restarts; ++r) {
      FitState p = start;
      if (r > 0) p.values = graph.randomValues(options.seed + 7919 * r, options.restartSpread);
      const double l = f.run(p, options.restartProbeIterations, true, true, coarse, res, false);
      if (l < bestProbe) bestProbe = l, bestState = p;
      if (res.cancelled) break;
    }
    s = bestState;
    remaining -= options.restartProbeIterations;
  }
  if (coarse > 0) {
    // coarse to fine: the searches and most steps on the downsampled part, the last steps at full
    // resolution from the coarse phase's best state
    const int fine = std::min(remaining, options.fineIterations);
    if (remaining > fine && !res.cancelled)
      f.run(s, remaining - fine, options.restarts == 0, true, coarse, res, true);
    res.coarseIterations = static_cast<int>(res.history.size());
    if (!res.cancelled) f.searchRoughness(s, 0, options.roughnessCandidates, res);
    if (fine > 0 && !res.cancelled)
      f.run(s, fine, options.restarts == 0 && remaining == fine, false, 0, res, true,
            remaining > fine ? options.fineLearningRateScale : 1.0f);
  } else if (!res.cancelled) {
    f.run(s, remaining, options.restarts == 0, true, 0, res, true);
    if (!res.cancelled && options.roughnessCandidates > 1) {
      // the line search last (no coarse phase: no fine steps after it)
      f.searchRoughness(s, 0, options.roughnessCandidates, res);
    }
  }
  PartFitter::Eval e = f.evaluate(0, f.maps(s.values), s.uv, s.roughness, options.specularSub, nullptr, &res.render);
  f.addPalette(e, s.values);
  res.values = s.values;
  res.uv = s.uv;
  res.roughness = s.roughness;
  const float mr = f.meanRoughness(s.values);
  res.roughnessScale = mr > 1e-4f ? s.roughness / mr : 1.0f;
  static_cast<PartFitLosses&>(res) = e;
  {
    const MaterialMaps m = f.maps(s.values);
    res.albedoAtCeiling = albedoFractionAtCeiling(m.albedo, 0.99f);
    const float worst =
        std::max({res.albedoAtCeiling[0], res.albedoAtCeiling[1], res.albedoAtCeiling[2]});
    res.albedoPinned = worst > 0.2f;
    if (res.albedoPinned)
      spdlog::warn(
          "fitPart {}: the albedo is pinned at 1.0 (texels >= 0.99: R {:.0f} %, G {:.0f} %, B "
          "{:.0f} %): light and "
          "albedo traded against each other (the part's light is too dim for its photo)",
          graph.name(), 100 * res.albedoAtCeiling[0], 100 * res.albedoAtCeiling[1],
          100 * res.albedoAtCeiling[2]);
  }
  res.seconds = timer.seconds();
  return res;
}

namespace {

void checkScoreInputs(const char* who, const PartGeometry& geometry, const cv::Mat& photo,
                      const TextureLossTarget& target, const PartFitOptions& options) {
  std::string err;
  PS_Check(options.IsValid(&err), who << ": invalid options: " << err);
  PS_Check(photo.type() == CV_32FC3 && photo.size() == geometry.imageSize,
           who << ": photo must be CV_32FC3 of the geometry's size");
  PS_Check(target.imageSize() == geometry.imageSize,
           who << ": texture-loss target and geometry sizes differ");
  PS_Check(geometry.size() > 0, who << ": the part has no pixels");
}

// One evaluation at full resolution of `maps` (graph null) or of the graph's maps at `values`.
PartFitResult scoreOnce(const MaterialGraph* graph, const MaterialMaps* maps,
                        const std::vector<float>& values, const UvParams& uv, float roughness,
                        const PartGeometry& geometry, const cv::Mat& photo,
                        const TextureLossTarget& target, PartFitOptions o, bool matchMeans) {
  const Timer timer;
  o.coarseLevels = o.searchLevels = 0;  // one level: nothing is fitted
  PartFitter f(graph, geometry, photo, target, o);
  PartFitResult res;
  res.values = values;
  res.uv = uv;
  res.roughness = roughness;
  if (o.roughnessPriorWeight > 0) res.roughnessPrior = f.prior();
  res.highlightPixels = f.highlightPixels();
  PartFitter::Eval e = f.evaluate(0, maps ? *maps : f.maps(values), uv, roughness,
                                  o.specularSub, nullptr, &res.render, matchMeans);
  if (graph) f.addPalette(e, values);
  static_cast<PartFitLosses&>(res) = e;
  res.initialLoss = e.loss;
  res.initialTextureLoss = e.lossTexture;
  res.seconds = timer.seconds();
  return res;
}

}  // namespace

PartFitResult scorePart(const MaterialGraph& graph, const PartFitResult& state,
                        const PartGeometry& geometry, const cv::Mat& photo,
                        const TextureLossTarget& target, const PartFitOptions& options,
                        bool matchMeans) {
  checkScoreInputs("scorePart", geometry, photo, target, options);
  PS_Check(static_cast<int>(state.values.size()) == graph.valueCount(),
           "scorePart: the state has " << state.values.size() << " values, graph " << graph.name()
                                       << " " << graph.valueCount());
  PartFitResult res = scoreOnce(&graph, nullptr, state.values, state.uv, state.roughness,
                                geometry, photo, target, options, matchMeans);
  res.roughnessScale = state.roughnessScale;
  return res;
}

PartFitResult scoreMaps(const MaterialMaps& maps, const std::string& category, const UvParams& uv,
                        float roughness, const PartGeometry& geometry, const cv::Mat& photo,
                        const TextureLossTarget& target, const PartFitOptions& options,
                        bool matchMeans) {
  checkScoreInputs("scoreMaps", geometry, photo, target, options);
  PS_Check(!maps.albedo.empty() && maps.albedo.type() == CV_32FC3 &&
               maps.albedo.rows == maps.albedo.cols,
           "scoreMaps: the albedo map must be a square CV_32FC3 image");
  PartFitOptions o = options;
  o.roughnessCategory = category;
  return scoreOnce(nullptr, &maps, {}, uv, roughness, geometry, photo, target, o, matchMeans);
}

}  // namespace ps
