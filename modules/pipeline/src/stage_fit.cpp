// Stage `fit`: per part, in parallel, the graph's parameters, mean roughness and UV transform
// (optim's fitPart) against the part's photo under incident0; homogeneous parts (and parts too
// small for a texture) in closed form (optim's fitHomogeneous).
#include <cstdlib>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/select/synthesis.hpp"
#include "stages.hpp"

namespace ps::pipeline {

namespace {

// The fit's version: 2 = the spectral UV prior and `balanced` at 100 steps; 3 = the
// full-resolution steps after the coarse phase at a quarter of the learning rate; 4 = `balanced`
// at 40 steps, `fast` at 30; 5 = the placement term (Eq. 9's pixel term) in `balanced`; 6 = the
// photo divided by its view's exposure (parts fitted in a view other than view 0); 7 = the
// roughness prior, highlight term, albedo ceiling and roughness line search
// (optim/roughness_prior.hpp); 8 = the start: the synthesis winner's short fit when select
// leaves one (SynthesisOptions::warmStartFit; PartWork::startValues, startUv), else the graph's
// defaults; 9 = a homogeneous part's
// roughness from highlights only, else the prior's centre (HomogeneousRoughness); 10 = a fitted
// texture that fails selection's pixel-error or contrast test is rejected for the homogeneous
// material (PartWork::textureRejected); 11 = a homogeneous albedo matches the photo's mean with
// the render clipped where an integer-coded photo clips (PartView::clip); 12 = the texture tests
// also at 2 x 2 cells (SynthesisOptions::coarseContrastScale); 13 = and the colour test
// (SynthesisOptions::maxChromaRatio), and a graph forced by `parts.<name>.graph` is kept whatever
// the tests say; 14 = the colour gamut test (SynthesisOptions::maxChromaOutside); 15 = the
// spectral shape in the loss of balanced and fast (PartFitOptions::bandShape); 16 = a graph of
// the category the scene gives (`parts.<name>.category`) is kept whatever the tests say when the
// selection options insist (SynthesisOptions::textureRequired); 17 = only then.
constexpr uint64_t kFitVersion = 17;

class FitStage : public Stage {
 public:
  FitStage() : Stage("fit", Unit::Part) {
    decl.version = kFitVersion;
    decl.scene = {"parts.{}.graph", "parts.{}.category", "views[].camera", "views[].image",
                  "views[].color_space", "options.seed"};
    decl.options = {"preset", "max_fit_iterations", "library", "work_width", "fit_views",
                    "selection"};
    decl.after = {"geometry", "align", "observe", "select", "incident0"};
    decl.writes = {
        "PartWork: values, uv, roughness, roughnessScale, albedo, loss, seconds, iterations, "
        "history, textureRejected; PartMode::Homogeneous where the texture is rejected"};
    decl.parallel = true;
  }

  bool applies(const Context& ctx, int u) const override {
    return ctx.parts[u].mode == PartMode::Fit || ctx.parts[u].mode == PartMode::Homogeneous;
  }

  // The graph's fit; false when cancelled. Sets *homogeneous when the fitted texture is rejected
  // (the part is then fitted as homogeneous); a graph the scene forces (`parts.<name>.graph`), or
  // one of the category it gives (`parts.<name>.category`) when the selection options insist
  // (SynthesisOptions::textureRequired), is the user's choice and is kept.
  bool fitTexture(const Reads& in, PartWork& p, const PartGeometry& geo, const cv::Mat& photo,
                  const cv::Mat& mask, bool forced, bool* homogeneous) const {
    PartFitOptions o = in.fitOptions();
    o.seed = Hasher().add(in.seed()).add(std::string_view(p.name)).digest();
    if (const auto cap = in.maxFitIterations()) o.maxIterations = std::min(o.maxIterations, *cap);
    // Ctrl-C stops a fit between two steps (a `paper` fit of one part runs for minutes)
    o.onProgress = [](const PartFitProgress&) { return !interruptRequested(); };
    const TextureLossTarget target(photo, mask);
    // from the synthesis winner's short fit when select left one (same graph), else from the
    // graph's defaults
    MaterialGraph graph = in.library().create(p.graph);
    UvParams startUv;
    if (!p.startValues.empty() && p.startValues.size() == graph.values().size()) {
      graph.setValues(p.startValues);
      startUv = p.startUv;
    }
    const PartFitResult r = fitPart(graph, geo, photo, target, o, startUv);
    if (r.cancelled) return false;  // not a result: nothing is stored, the runner stops
    spdlog::debug("fit {}: spectral prior {} (log-scale {:.2f}, rotation {:.0f} deg, response "
                  "{:.2f}); fitted log-scale {:.2f}, rotation {:.0f} deg",
                  p.name, r.spectrum.ok ? "used" : "not used", r.spectrum.logScale,
                  degrees(r.spectrum.rotation), r.spectrum.response, r.uv.logScale,
                  degrees(r.uv.rotation));
    // texture only where the photo shows one, judged on the full fit as select judges its short
    // fits (select/synthesis.hpp, textureEvidence): a fitted render that misses the photo's
    // pixels by more than maxPixelErrorRatio x the homogeneous material's, or shows more than
    // maxContrastRatio x the photo's typical local contrast, or more than maxChromaRatio x its
    // colour spread, or more than maxChromaOutside of its pixels in colours the photo lacks (a
    // test made here only: a short fit's colours have not settled), is not the photo's texture.
    // The full fit can drift there from a short fit that passed. A graph the user forced is not
    // second-guessed.
    const SynthesisOptions selection = in.synthesisOptions();
    if (!forced && selection.anyTextureTest()) {
      const PartFitResult flat = homogeneousPartFit(in.library(), geo, photo, target, o);
      const TextureEvidence e = textureEvidence(r.render, flat.render, photo, geo, selection);
      if (!e.ok()) {
        spdlog::info(
            "fit {}: {} rejected for the homogeneous material: pixel RMSE {:.4f} against its "
            "{:.4f}, typical local contrast {:.3f} against the photo's {:.3f} ({:.3f} against "
            "{:.3f} over {} x {} cells), chromaticity spread {:.3f} against the photo's {:.3f}, "
            "{:.0f} % of its pixels in colours the photo lacks (the flat render's {:.0f} %)",
            p.name, p.graph, e.pixelRmse, e.flatPixelRmse, e.contrast, e.photoContrast,
            e.coarseContrast, e.photoCoarseContrast, selection.coarseContrastScale,
            selection.coarseContrastScale, e.chroma, e.photoChroma, 100 * e.chromaOutside,
            100 * e.flatChromaOutside);
        p.textureRejected = p.graph;
        p.values.clear();
        p.mode = PartMode::Homogeneous;
        *homogeneous = true;
        return true;
      }
    }
    if (const char* debug = std::getenv("PS_DEBUG_DIR"); debug && *debug) {
      // photo over the fitted mask | the fit's render, for looking at what the fit did
      cv::Mat masked = cv::Mat::zeros(photo.size(), CV_32FC3), side;
      photo.copyTo(masked, mask);
      cv::hconcat(masked, r.render, side);
      fs::create_directories(debug);
      io::writeImage(fs::path(debug) / ("fit-" + p.name + ".png"), side);
    }
    p.values = r.values;
    p.uv = r.uv;
    p.roughness = r.roughness;
    p.roughnessScale = r.roughnessScale;
    p.loss = r.loss;
    p.iterations = r.iterations;
    p.history = r.history;
    return true;
  }

  bool compute(Context& ctx, const Reads& in, int u) override {
    PartWork& p = ctx.parts[u];
    const ViewWork& view = ctx.views[p.view];
    Timer timer;
    // the photo as the render sees it: divided by the view's exposure (lights0's, or lights1's)
    const cv::Mat photo = partPhoto(in.photo(p.view), view, p.id) / ctx.viewExposure(p.view);
    const cv::Mat& mask = view.fitMask.at(p.id);
    const PartGeometry geo = preparePartGeometry(
        view.gbuffer, in.camera(p.view).position().cast<float>(), view.grid, mask, p.id);
    p.textureRejected.clear();
    bool homogeneous = p.mode == PartMode::Homogeneous || geo.size() < kMinFitPixels;
    if (!homogeneous &&
        !fitTexture(in, p, geo, photo, mask,
                    in.partGraph(u).has_value() || in.categoryInsisted(u), &homogeneous))
      return false;
    if (homogeneous) {
      const HomogeneousFit f =
          p.mode == PartMode::Homogeneous
              ? fitHomogeneousPart(ctx, in, p, geo, photo, in.budget().refineCandidates)
              : fitHomogeneous({{&geo, photo, in.photoClip(p.view, ctx.viewExposure(p.view))}},
                               roughnessGrid(in.budget().refineCandidates),
                               homogeneousRoughness(in.fitOptions()));
      p.mode = PartMode::Homogeneous;
      p.graph = p.category = "homogeneous";
      p.albedo = f.albedo;
      p.roughness = f.roughness;
      p.loss = f.loss;
      p.iterations = 0;
      p.history.clear();
    }
    p.seconds = timer.seconds();
    spdlog::info("fit {}: {} ({}), loss {:.4f}, {} iterations, {:.1f} s", p.name, p.graph,
                 p.category, p.loss, p.iterations, p.seconds);
    return true;
  }
  void save(const Context& ctx, int u, Archive& a) const override {
    const PartWork& p = ctx.parts[u];
    a.putVector(p.values);
    for (float f : {p.uv.rotation, p.uv.logScale, p.uv.offset.x(), p.uv.offset.y(), p.roughness,
                    p.roughnessScale, p.albedo.x(), p.albedo.y(), p.albedo.z()})
      a.put(f);
    a.put(p.loss);
    a.put(p.seconds);
    a.put<int32_t>(p.iterations);
    a.putVector(p.history);
    a.putString(p.textureRejected);
  }
  bool load(Context& ctx, const Reads&, int u, Archive& a) override {
    PartWork& p = ctx.parts[u];
    p.values = a.getVector<float>();
    p.uv.rotation = a.get<float>();
    p.uv.logScale = a.get<float>();
    p.uv.offset.x() = a.get<float>();
    p.uv.offset.y() = a.get<float>();
    p.roughness = a.get<float>();
    p.roughnessScale = a.get<float>();
    for (int k = 0; k < 3; ++k) p.albedo[k] = a.get<float>();
    p.loss = a.get<double>();
    p.seconds = a.get<double>();
    p.iterations = a.get<int32_t>();
    p.history = a.getVector<double>();
    p.textureRejected = a.getString();
    return true;
  }
  // a part fitted as homogeneous (too few pixels) has no graph values: the mode follows the
  // result whether it was computed or loaded
  void finish(Context& ctx, const Reads&) override {
    for (PartWork& p : ctx.parts)
      if ((p.mode == PartMode::Fit || p.mode == PartMode::Homogeneous) && p.values.empty()) {
        p.mode = PartMode::Homogeneous;
        p.graph = p.category = "homogeneous";
      }
  }
};

}  // namespace

std::unique_ptr<Stage> makeFitStage() {
  return std::make_unique<FitStage>();
}

}  // namespace ps::pipeline
