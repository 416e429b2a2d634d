#include "photoscene/select/synthesis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include "photoscene/core/error.hpp"
#include "photoscene/core/parallel.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/features/texture_contrast.hpp"
#include "photoscene/optim/homogeneous_fit.hpp"

namespace ps {

namespace {
constexpr const char* kHomogeneous = "homogeneous";
// fewer pixels with their whole contrast window in the part: its median says little
constexpr int kMinContrastPixels = 64;

/// What a textured render adds to the flat render's own amount of something (contrast, colour
/// spread: the incident-light grid gives the flat render some), taken off in quadrature.
double beyondFlat(double textured, double flat) {
  return std::sqrt(std::max(0.0, textured * textured - flat * flat));
}

cv::Mat maskOf(const PartGeometry& geometry, cv::Size size) {
  cv::Mat m = cv::Mat::zeros(size, CV_8UC1);
  for (const cv::Point& q : geometry.pixels) m.at<uint8_t>(q) = 255;
  return m;
}

/// Typical local contrast at full resolution and at the coarse scale (none where the options
/// make no contrast test, or no coarse one), and the chromaticity spread (none without a chroma
/// test).
struct Contrasts {
  LocalContrast fine, coarse;
  ChromaSpread chroma;
  double chromaOutside = 0;  ///< share outside the photo's gamut (a render's; 0 for the photo)
};
/// The photo's colours for the gamut test (empty without it).
ChromaGamut photoGamut(const cv::Mat& photo, const cv::Mat& mask, const SynthesisOptions& options) {
  return options.maxChromaOutside > 0 ? chromaGamut(photo, mask) : ChromaGamut{};
}
/// `gamut`: the photo's colours, for a render (nullptr for the photo itself)
Contrasts contrastsOf(const cv::Mat& image, const cv::Mat& mask, const SynthesisOptions& options,
                      const ChromaGamut* gamut = nullptr) {
  Contrasts c;
  if (options.maxChromaRatio > 0 || options.maxChromaOutside > 0)
    c.chroma = chromaSpread(image, mask);  // its pixel count gates both colour tests
  if (gamut) c.chromaOutside = chromaOutside(*gamut, image, mask);
  if (options.maxContrastRatio <= 0) return c;
  c.fine = typicalLocalContrast(image, mask);
  if (options.coarseContrastScale > 1) {
    LocalContrastOptions o;
    o.scale = options.coarseContrastScale;
    c.coarse = typicalLocalContrast(image, mask, o);
  }
  return c;
}

/// The evidence from a render's and the photo's contrasts and pixel errors, judged.
TextureEvidence evidence(double pixelRmse, double flatPixelRmse, bool hasFlat,
                         const Contrasts& render, const Contrasts& flat, const Contrasts& photo,
                         const SynthesisOptions& options) {
  TextureEvidence e;
  e.pixelRmse = pixelRmse;
  e.flatPixelRmse = flatPixelRmse;
  e.hasFlat = hasFlat;
  e.contrast = render.fine.median;
  e.photoContrast = photo.fine.median;
  e.photoContrastPixels = photo.fine.pixels;
  e.coarseContrast = render.coarse.median;
  e.photoCoarseContrast = photo.coarse.median;
  e.photoCoarsePixels = photo.coarse.pixels;
  e.flatCoarseContrast = flat.coarse.median;  // 0 without a flat render (Contrasts{})
  e.chroma = render.chroma.spread;
  e.photoChroma = photo.chroma.spread;
  e.photoChromaPixels = photo.chroma.pixels;
  e.flatChroma = flat.chroma.spread;
  e.chromaOutside = render.chromaOutside;
  e.flatChromaOutside = flat.chromaOutside;
  e.judge(options);
  return e;
}
}  // namespace

double maskedRmse(const cv::Mat& a, const cv::Mat& b, const std::vector<cv::Point>& pixels) {
  if (pixels.empty() || a.empty() || a.size() != b.size()) return 0;
  double sum = 0;
  for (const cv::Point& q : pixels) {
    const cv::Vec3f d = a.at<cv::Vec3f>(q) - b.at<cv::Vec3f>(q);
    sum += d.dot(d);
  }
  return std::sqrt(sum / (3.0 * pixels.size()));
}

PartFitResult homogeneousPartFit(const GraphLibrary& library, const PartGeometry& geometry,
                                 const cv::Mat& photo, const TextureLossTarget& target,
                                 const PartFitOptions& fit) {
  // in closed form (optim's fitHomogeneous: the albedo matching the photo's mean per channel,
  // the roughness as the fit's roughness terms say, HomogeneousRoughness), then scored by the
  // same loss without steps; nothing to place: no UV search, no spectral prior
  MaterialGraph graph = library.create(kHomogeneous);
  const HomogeneousFit h =
      fitHomogeneous(geometry, photo, roughnessGrid(5), homogeneousRoughness(fit));
  graph.setParameter("albedo", {h.albedo.x(), h.albedo.y(), h.albedo.z()});
  graph.setParameter("roughness", {h.roughness});
  PartFitOptions o = fit;
  o.maxIterations = 0;
  o.restarts = 0;
  o.searchRotations = o.searchLogScales = o.searchOffsets = 1;
  o.refineSteps = 0;
  o.spectrumScaleWindow = 0;
  o.placementOffsets = 0;
  return fitPart(graph, geometry, photo, target, o);
}

namespace {
/// a / b, where a test's quantity a is compared with its bar b: <= 1 passes (b = 0: 0 for a <= 0,
/// else infinity; NaN fails)
double toBar(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::infinity();
  if (b > 0) return a / b;
  return a <= 0 ? 0.0 : std::numeric_limits<double>::infinity();
}
}  // namespace

double TextureEvidence::worstRatio(const SynthesisOptions& options, bool* pixelsPass,
                                   bool* contrastPass, bool* chromaPass) const {
  double pixelRatio = 0, contrastRatio = 0, chromaRatio = 0;
  if (options.maxPixelErrorRatio > 0 && hasFlat)
    pixelRatio = toBar(pixelRmse, options.maxPixelErrorRatio * flatPixelRmse);
  // the contrast test needs a photo contrast measured on enough pixels (thin parts: no test)
  if (options.maxContrastRatio > 0 && photoContrastPixels >= kMinContrastPixels)
    contrastRatio = toBar(contrast, options.maxContrastRatio * photoContrast);
  // and structure the photo does not show at the coarser scale, the flat render's own (the
  // grid's noise) taken off in quadrature (too few cells: no such test)
  if (options.maxContrastRatio > 0 && options.coarseContrastScale > 1 &&
      photoCoarsePixels >= kMinContrastPixels)
    contrastRatio = std::max(contrastRatio, toBar(beyondFlat(coarseContrast, flatCoarseContrast),
                                                  options.maxContrastRatio * photoCoarseContrast));
  // no more colours than the photo shows, the flat render's own (its light's) taken off
  if (options.maxChromaRatio > 0 && photoChromaPixels >= kMinContrastPixels)
    chromaRatio = toBar(beyondFlat(chroma, flatChroma), options.maxChromaRatio * photoChroma);
  // and hardly any pixel in colours the photo does not show, beyond the flat render's own
  if (options.maxChromaOutside > 0 && photoChromaPixels >= kMinContrastPixels)
    chromaRatio = std::max(chromaRatio,
                           toBar(chromaOutside - flatChromaOutside, options.maxChromaOutside));
  if (pixelsPass) *pixelsPass = pixelRatio <= 1;
  if (contrastPass) *contrastPass = contrastRatio <= 1;
  if (chromaPass) *chromaPass = chromaRatio <= 1;
  return std::max({pixelRatio, contrastRatio, chromaRatio});
}

void TextureEvidence::judge(const SynthesisOptions& options) {
  testRatio = worstRatio(options, &pixelsOk, &contrastOk, &chromaOk);
}

TextureEvidence textureEvidence(const cv::Mat& textured, const cv::Mat& flat, const cv::Mat& photo,
                                const PartGeometry& geometry, const SynthesisOptions& options) {
  const cv::Mat mask = maskOf(geometry, photo.size());
  const ChromaGamut gamut = photoGamut(photo, mask, options);
  return evidence(maskedRmse(textured, photo, geometry.pixels),
                  maskedRmse(flat, photo, geometry.pixels), !flat.empty(),
                  contrastsOf(textured, mask, options, &gamut),
                  flat.empty() ? Contrasts{} : contrastsOf(flat, mask, options, &gamut),
                  contrastsOf(photo, mask, options), options);
}

bool SynthesisOptions::IsValid(std::string* error) const {
  std::ostringstream os;
  if (shortlist < 0)
    os << "shortlist must be >= 0, got " << shortlist;
  else if (categories < 0)
    os << "categories must be >= 0, got " << categories;
  else if (voteK < 1)
    os << "voteK must be >= 1, got " << voteK;
  else if (steps < 0)
    os << "steps must be >= 0, got " << steps;
  else if (!(textureMargin >= 0 && textureMargin < 1))
    os << "textureMargin must be in [0, 1), got " << textureMargin;
  else if (!(maxPixelErrorRatio >= 0))
    os << "maxPixelErrorRatio must be >= 0, got " << maxPixelErrorRatio;
  else if (!(maxContrastRatio >= 0))
    os << "maxContrastRatio must be >= 0, got " << maxContrastRatio;
  else if (coarseContrastScale < 0)
    os << "coarseContrastScale must be >= 0, got " << coarseContrastScale;
  else if (!(maxChromaRatio >= 0))
    os << "maxChromaRatio must be >= 0, got " << maxChromaRatio;
  else if (!(maxChromaOutside >= 0 && maxChromaOutside <= 1))
    os << "maxChromaOutside must be in [0, 1], got " << maxChromaOutside;
  else if (bandShape && !(*bandShape >= 0))
    os << "bandShape must be >= 0, got " << *bandShape;
  else if (minHeldOutPixels < 1)
    os << "minHeldOutPixels must be >= 1, got " << minHeldOutPixels;
  if (error) *error = os.str();
  return os.str().empty();
}

bool splitPartInHalves(const PartGeometry& geometry, int minPixels, std::vector<int> halves[2]) {
  const int n = geometry.size();
  if (n < 2 || n / 2 < minPixels) return false;
  // the principal axis of the pixel positions (the 2 x 2 covariance's leading eigenvector)
  double mx = 0, my = 0;
  for (const cv::Point& q : geometry.pixels) mx += q.x, my += q.y;
  mx /= n, my /= n;
  double cxx = 0, cyy = 0, cxy = 0;
  for (const cv::Point& q : geometry.pixels) {
    const double dx = q.x - mx, dy = q.y - my;
    cxx += dx * dx, cyy += dy * dy, cxy += dx * dy;
  }
  const double angle = 0.5 * std::atan2(2 * cxy, cxx - cyy);
  const double ax = std::cos(angle), ay = std::sin(angle);
  std::vector<std::pair<double, int>> along(n);
  for (int k = 0; k < n; ++k)
    along[k] = {ax * geometry.pixels[k].x + ay * geometry.pixels[k].y, k};
  // ties broken by index: the same halves on every platform
  std::nth_element(along.begin(), along.begin() + n / 2, along.end());
  halves[0].clear();
  halves[1].clear();
  for (int k = 0; k < n; ++k) halves[k < n / 2 ? 0 : 1].push_back(along[k].second);
  for (int h = 0; h < 2; ++h) std::sort(halves[h].begin(), halves[h].end());
  return true;
}

std::vector<std::string> synthesisFinalists(const GraphLibrary& library,
                                            const std::vector<GraphVote>& votes,
                                            const SynthesisOptions& options) {
  std::vector<std::string> out;
  std::set<std::string> categories;
  auto usable = [&](const GraphVote& v) {
    return v.graph != kHomogeneous && library.contains(v.graph) &&
           std::find(out.begin(), out.end(), v.graph) == out.end();
  };
  for (const GraphVote& v : votes) {
    if (static_cast<int>(out.size()) >= options.shortlist) break;
    if (!usable(v)) continue;
    out.push_back(v.graph);
    categories.insert(library.get(v.graph).category());
  }
  // category diversity: the vote's best graph of each category not yet in
  for (const GraphVote& v : votes) {
    if (static_cast<int>(categories.size()) >= options.categories) break;
    if (!usable(v)) continue;
    const std::string c = library.get(v.graph).category();
    if (categories.count(c)) continue;
    out.push_back(v.graph);
    categories.insert(c);
  }
  if (options.homogeneous && library.contains(kHomogeneous)) out.push_back(kHomogeneous);
  return out;
}

SynthesisChoice chooseBySynthesis(const GraphLibrary& library, const std::vector<GraphVote>& votes,
                                  const PartGeometry& geometry, const cv::Mat& photo,
                                  const TextureLossTarget& target, const PartFitOptions& callerFit,
                                  const SynthesisOptions& options,
                                  const ExemplarBankOptions* bank) {
  std::string why;
  PS_Check(options.IsValid(&why), "invalid SynthesisOptions: " << why);
  PartFitOptions fit = callerFit;
  if (options.bandShape) fit.bandShape = *options.bandShape;
  const Timer timer;
  const std::vector<std::string> names = synthesisFinalists(library, votes, options);
  SynthesisChoice out;
  out.finalists.resize(names.size());
  double total = 0;
  for (const GraphVote& v : votes) total += v.weight;
  for (size_t i = 0; i < names.size(); ++i) {
    SynthesisFinalist& f = out.finalists[i];
    f.graph = names[i];
    f.category = library.get(names[i]).category();
    for (const GraphVote& v : votes)
      if (v.graph == f.graph) {
        if (total > 0) f.vote = v.weight / total;
        f.draw = v.nearestDraw;
      }
  }
  // the part's mask (the geometry's pixels) and the photo's typical local contrast over it
  const cv::Mat partMask = maskOf(geometry, photo.size());
  const Contrasts photoContrast = contrastsOf(photo, partMask, options);
  const ChromaGamut gamut = photoGamut(photo, partMask, options);
  out.photoContrast = photoContrast.fine.median;
  out.photoCoarseContrast = photoContrast.coarse.median;
  out.photoChroma = photoContrast.chroma.spread;
  // held-back pixels: the part in two halves, each with its own texture-loss target
  std::vector<int> halfIndex[2];
  out.heldOut = options.heldOut && splitPartInHalves(geometry, options.minHeldOutPixels, halfIndex);
  std::vector<PartGeometry> halves;
  std::vector<TextureLossTarget> halfTargets;
  float halfRoughness[2] = {0, 0};
  if (out.heldOut)
    for (int h = 0; h < 2; ++h) {
      halves.push_back(subsetPartGeometry(geometry, halfIndex[h]));
      halfTargets.emplace_back(photo, maskOf(halves[h], photo.size()), target.options());
      halfRoughness[h] =
          fitHomogeneous(halves[h], photo, roughnessGrid(5), homogeneousRoughness(fit)).roughness;
    }
  parallelFor(0, static_cast<int64_t>(names.size()), [&](int64_t i) {
    SynthesisFinalist& f = out.finalists[i];
    PartFitOptions o = fit;
    o.maxIterations = options.steps;
    o.fineIterations = std::min(o.fineIterations, options.steps / 3);
    o.restarts = 0;
    o.heldParameters = options.heldParameters;
    MaterialGraph graph = library.create(f.graph);
    if (options.startFromNearestDraw && bank && f.draw > 0 && f.graph != kHomogeneous)
      graph.setValues(bankDrawValues(graph, *bank, f.draw));
    const Timer t;
    auto shortFit = [&](const PartGeometry& g, const TextureLossTarget& tg) {
      return f.graph == kHomogeneous ? homogeneousPartFit(library, g, photo, tg, fit)
                                     : fitPart(graph, g, photo, tg, o);
    };
    if (!out.heldOut) {
      f.fit = shortFit(geometry, target);
      f.loss = f.fitLoss = f.fit.loss;
    } else {
      // fitted on each half, scored on the other with the render's channel means matched to the
      // held-back photo's and the held-back half's own closed-form roughness: what is tested is
      // the freedom a graph has beyond the mean colour and gloss that every finalist has (its
      // pattern); the mean's error across the part is the incident light's, common to all, and a
      // roughness fitted to one bright streak is a gloss the other half need not share. Scored by
      // the data terms (the regularisers score values, not pixels), the halves' losses combined
      // by their geometric mean: each half counts by its ratio, so a half with strong edges
      // (losses 100x the plain half's) does not outvote the other. The tests below read the fits'
      // renders on their own halves (what the fit stage's full fit will show).
      const PartFitResult fits[2] = {shortFit(halves[0], halfTargets[0]),
                                     shortFit(halves[1], halfTargets[1])};
      double logLoss = 0;
      f.fitLoss = 0;
      for (int h = 0; h < 2; ++h) {
        PartFitResult state = fits[1 - h];
        state.roughness = halfRoughness[h];
        const PartFitResult held =
            scorePart(graph, state, halves[h], photo, halfTargets[h], fit, true);
        logLoss += 0.5 * std::log(std::max(held.lossData, 1e-12));
        f.fitLoss += 0.5 * fits[h].loss;
      }
      f.loss = std::exp(logLoss);
      f.fit = fits[0];
      f.fit.render = fits[0].render + fits[1].render;  // each zero off its half
    }
    f.pixelRmse = maskedRmse(f.fit.render, photo, geometry.pixels);
    const Contrasts c = contrastsOf(f.fit.render, partMask, options, &gamut);
    f.contrast = c.fine.median;
    f.coarseContrast = c.coarse.median;
    f.chroma = c.chroma.spread;
    f.chromaOutside = c.chromaOutside;
    f.seconds = t.seconds();
  });
  std::stable_sort(
      out.finalists.begin(), out.finalists.end(),
      [](const SynthesisFinalist& a, const SynthesisFinalist& b) { return a.loss < b.loss; });
  // the winner: the best textured finalist that passes the pixel-error and contrast tests,
  // unless the homogeneous material is within the margin of its loss
  const auto homogeneous =
      std::find_if(out.finalists.begin(), out.finalists.end(),
                   [](const SynthesisFinalist& f) { return f.graph == kHomogeneous; });
  // the gamut test judges the full fit only (the fit stage's textureEvidence): a short fit's
  // colours have not converged, and a finalist turned down for them hands the part to the next
  // textured finalist instead of the flat material
  SynthesisOptions finalistTests = options;
  finalistTests.maxChromaOutside = 0;
  for (SynthesisFinalist& f : out.finalists) {
    if (f.graph == kHomogeneous || homogeneous == out.finalists.end()) continue;
    Contrasts render, flat;
    render.fine.median = f.contrast;
    render.coarse.median = f.coarseContrast;
    flat.fine.median = homogeneous->contrast;
    flat.coarse.median = homogeneous->coarseContrast;
    render.chroma.spread = f.chroma;
    flat.chroma.spread = homogeneous->chroma;
    const TextureEvidence e = evidence(f.pixelRmse, homogeneous->pixelRmse, true, render, flat,
                                       photoContrast, finalistTests);
    f.qualifies = e.ok();
    f.testRatio = e.testRatio;
  }
  const auto textured =
      std::find_if(out.finalists.begin(), out.finalists.end(), [](const SynthesisFinalist& f) {
        return f.graph != kHomogeneous && f.qualifies;
      });
  const SynthesisFinalist* win = nullptr;
  if (options.textureRequired) {
    // the user's category: a textured finalist wins whatever the homogeneous loss; if none
    // passes the tests, the one nearest to its bars (the smallest worst ratio)
    if (textured != out.finalists.end())
      win = &*textured;
    else
      for (const SynthesisFinalist& f : out.finalists)
        if (f.graph != kHomogeneous && (!win || f.testRatio < win->testRatio)) win = &f;
  } else if (textured == out.finalists.end())
    win = homogeneous == out.finalists.end() ? nullptr : &*homogeneous;
  else if (homogeneous == out.finalists.end() ||
           textured->loss < (1 - options.textureMargin) * homogeneous->loss)
    win = &*textured;
  else
    win = &*homogeneous;
  if (win) {
    out.graph = win->graph;
    out.category = win->category;
  } else if (!votes.empty()) {
    out.graph = votes.front().graph;
    out.category = votes.front().category;
  }
  out.seconds = timer.seconds();
  return out;
}

}  // namespace ps
