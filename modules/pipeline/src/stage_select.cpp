// Stage `select`: per part, its material graph: the user's (`parts.<name>.graph`), or one of the
// user's category (`parts.<name>.category`) chosen as below among that category's graphs, homogeneous
// below the small-part threshold (counted over the part's interior: a chair's thin frame shows
// its outline, not a texture), else the kNN vote over the exemplar bank shortlists and the
// shortlist's short fits on the part under incident0 decide (select/synthesis.hpp).
#include <cstdlib>

#include "photoscene/core/log.hpp"

#include "photoscene/io.hpp"
#include "photoscene/select.hpp"
#include "stages.hpp"

namespace ps::pipeline {

namespace {

class SelectStage : public Stage {
 public:
  SelectStage() : Stage("select", Unit::Part) {
    decl.scene = {"parts.{}.graph", "parts.{}.category", "views[].camera", "views[].image",
                  "views[].color_space", "options.seed"};
    decl.options = {"library", "work_width", "preset", "selection"};
    decl.after = {"parts", "geometry", "align", "observe", "incident0"};
    decl.writes = {"PartWork::graph",      "PartWork::category",  "PartWork::runnersUp",
                   "PartWork::candidates", "PartWork::finalists", "PartWork::startValues",
                   "PartWork::startUv",    "PartMode::Homogeneous"};
    // 2: the cached entry holds the vote's top 5 (materials fit.candidates); 3: selection by
    // synthesis (fit.finalists); 4: finalists start from their nearest draw; 5: the winner's
    // short fit is where the fit starts (PartWork::startValues, startUv); 6: the homogeneous
    // finalist's roughness from highlights only (HomogeneousRoughness); 7: a textured winner's
    // pixel error at most maxPixelErrorRatio x the homogeneous finalist's; 8: a textured
    // winner's typical local contrast at most maxContrastRatio x the photo's, and the best
    // textured finalist that passes both tests is the one weighed against homogeneous; 9: the
    // faces of a part brought to one level before the vote (preparePartTexture), and the
    // contrast test made again at 2 x 2 cells (SynthesisOptions::coarseContrastScale); 10: a
    // part's size for the small-part rule is its interior (interiorPixels), not its pixel count;
    // 11: a textured finalist's chromaticity spread at most maxChromaRatio x the photo's; 12:
    // finalists fitted on one half of the part and scored on the other (SynthesisOptions::heldOut);
    // 13: each finalist's share of its render in colours the photo lacks (fit.finalists[].
    // chroma_outside; the fit stage judges the full fit by it, SynthesisOptions::maxChromaOutside);
    // 14: the finalists' short fits weigh the spectral shape (SynthesisOptions::bandShape); 15:
    // a part's given category (`parts.<name>.category`) restricts the vote and the finalists; 16:
    // weighed against the homogeneous material unless SynthesisOptions::textureRequired; 17: a
    // given category's finalists include its graphs no neighbour voted for (nearest row first)
    decl.version = 17;
  }

  bool applies(const Context& ctx, int u) const override {
    return ctx.parts[u].mode == PartMode::Fit;
  }

  bool compute(Context& ctx, const Reads& in, int u) override {
    PartWork& p = ctx.parts[u];
    const ViewWork& view = ctx.views[p.view];
    const Camera& camera = in.camera(p.view);
    p.runnersUp.clear();
    p.candidates.clear();
    p.finalists.clear();
    p.photoContrast = p.photoCoarseContrast = p.photoChroma = 0;
    p.heldOut = false;
    p.startValues.clear();
    p.startUv = UvParams();
    // the user's category (`parts.<name>.category`): only its graphs vote and are finalists, and
    // they are weighed against the homogeneous material as any part's are (a texture only where
    // the photo shows one, and never one of another category). With the selection options'
    // textureRequired the user insists: one of the category's graphs wins whatever the
    // homogeneous loss, and the small-part rule does not apply.
    const std::optional<std::string>& given = in.partCategory(u);
    const bool insist = in.categoryInsisted(u);
    if (const auto& forced = in.partGraph(u)) {
      p.graph = *forced;
    } else if (given && *given == "homogeneous") {
      p.graph = "homogeneous";
    } else if (!insist && isSmallPart(view.photoMask.at(p.id), camera.width(), camera.height())) {
      p.graph = "homogeneous";
    } else {
      if (!bank_) {
        bool cached = false;
        bank_ = std::make_unique<ExemplarBank>(
            ExemplarBank::loadOrBuild(in.library(), {}, in.bankCache(), &cached));
        spdlog::info("exemplar bank: {} exemplars {}", bank_->rows(), cached ? "loaded" : "built");
      }
      // the part's photo in the render frame, where the G-buffer UVs are: selectForPart unwarps
      // it into texture space and removes smooth shading before the kNN vote
      const cv::Mat& photo = in.photo(p.view);
      const cv::Mat& fit = view.fitMask.at(p.id);
      SynthesisOptions synthesis = in.synthesisOptions();
      synthesis.textureRequired = insist;  // only for a part whose category the scene gives
      PartSelectionOptions so;
      if (synthesis.shortlist > 0 || synthesis.categories > 0) so.k = synthesis.voteK;
      if (given) {
        // as many short fits as without it, all of them on the category's graphs
        so.category = *given;
        synthesis.shortlist += std::max(0, synthesis.categories - 1);
        synthesis.categories = std::min(synthesis.categories, 1);
      }
      const bool aligned = cv::countNonZero(fit) > 0;
      const GraphChoice c =
          aligned ? selectForPart(*bank_, partPhoto(photo, view, p.id), fit, view.gbuffer.uv,
                                  cv::Mat(), so)
                  : selectForPart(*bank_, photo, view.photoMask.at(p.id), cv::Mat(), cv::Mat(), so);
      p.graph = c.graph;
      if (const char* debug = std::getenv("PS_DEBUG_DIR"); debug && *debug && aligned) {
        // what the vote saw: the part's texture as selectForPart prepares it
        const PartTexture t = preparePartTexture(partPhoto(photo, view, p.id), fit,
                                                 view.gbuffer.uv, cv::Mat(),
                                                 bank_->options().shadingSigma, so);
        fs::create_directories(debug);
        io::writeImage(fs::path(debug) / ("select-" + p.name + ".png"), t.image);
      }
      if ((synthesis.shortlist > 0 || synthesis.categories > 0) && aligned) {
        // the vote shortlists; short fits on the part itself decide (and texture or not)
        // the photo as the render sees it: divided by the view's exposure (as the fit stage)
        const cv::Mat part = partPhoto(photo, view, p.id) / ctx.viewExposure(p.view);
        const PartGeometry geo = preparePartGeometry(view.gbuffer, camera.position().cast<float>(),
                                                     view.grid, fit, p.id);
        if (geo.size() >= 16) {
          PartFitOptions o = in.fitOptions();
          o.seed = Hasher().add(in.seed()).add(std::string_view(p.name)).digest();
          const SynthesisChoice s =
              chooseBySynthesis(in.library(), c.votes, geo, part, TextureLossTarget(part, fit), o,
                                synthesis, &bank_->options());
          if (!s.graph.empty()) p.graph = s.graph;
          p.photoContrast = s.photoContrast;
          p.photoCoarseContrast = s.photoCoarseContrast;
          p.photoChroma = s.photoChroma;
          p.heldOut = s.heldOut;
          for (const SynthesisFinalist& f : s.finalists) {
            p.finalists.push_back({f.graph, f.category, f.vote, f.loss, f.seconds, f.fitLoss,
                                   f.pixelRmse, f.contrast, f.coarseContrast, f.chroma,
                                   f.chromaOutside, f.qualifies});
            // the fit goes on from the winner's short fit instead of starting over
            if (synthesis.warmStartFit && f.graph == p.graph && f.graph != "homogeneous" &&
                p.startValues.empty()) {
              p.startValues = f.fit.values;
              p.startUv = f.fit.uv;
            }
          }
          spdlog::info("select {}: {} of {} finalists by synthesis ({:.1f} s)", p.name, p.graph,
                       s.finalists.size(), s.seconds);
        }
      }
      for (size_t i = 1; i < c.votes.size() && i < 4; ++i) p.runnersUp.push_back(c.votes[i].graph);
      // the top 5 with their share of the vote, for the materials file and the report
      double total = 0;
      for (const GraphVote& v : c.votes) total += v.weight;
      for (size_t i = 0; i < c.votes.size() && i < 5; ++i)
        p.candidates.push_back({c.votes[i].graph, c.votes[i].category,
                                total > 0 ? c.votes[i].weight / total : 0, c.votes[i].count});
    }
    p.category = in.library().get(p.graph).category();
    if (p.category == "homogeneous") p.mode = PartMode::Homogeneous;
    return true;
  }
  void save(const Context& ctx, int u, Archive& a) const override {
    const PartWork& p = ctx.parts[u];
    a.putString(p.graph);
    a.putString(p.category);
    a.put<int32_t>(static_cast<int32_t>(p.runnersUp.size()));
    for (const std::string& r : p.runnersUp) a.putString(r);
    a.put<int32_t>(static_cast<int32_t>(p.candidates.size()));
    for (const GraphVote& v : p.candidates) {
      a.putString(v.graph);
      a.putString(v.category);
      a.put(v.weight);
      a.put<int32_t>(v.count);
    }
    a.put<int32_t>(static_cast<int32_t>(p.finalists.size()));
    for (const PartWork::Finalist& f : p.finalists) {
      a.putString(f.graph);
      a.putString(f.category);
      for (double x : {f.vote, f.loss, f.seconds, f.fitLoss, f.pixelRmse, f.contrast,
                       f.coarseContrast, f.chroma, f.chromaOutside})
        a.put(x);
      a.put<uint8_t>(f.qualifies ? 1 : 0);
    }
    a.put(p.photoContrast);
    a.put(p.photoCoarseContrast);
    a.put(p.photoChroma);
    a.put<uint8_t>(p.heldOut ? 1 : 0);
    a.putVector(p.startValues);
    for (float f : {p.startUv.rotation, p.startUv.logScale, p.startUv.offset.x(),
                    p.startUv.offset.y()})
      a.put(f);
  }
  bool load(Context& ctx, const Reads&, int u, Archive& a) override {
    PartWork& p = ctx.parts[u];
    p.graph = a.getString();
    p.category = a.getString();
    const int n = a.get<int32_t>();
    p.runnersUp.clear();
    for (int i = 0; i < n; ++i) p.runnersUp.push_back(a.getString());
    p.candidates.resize(a.get<int32_t>());
    for (GraphVote& v : p.candidates) {
      v.graph = a.getString();
      v.category = a.getString();
      v.weight = a.get<double>();
      v.count = a.get<int32_t>();
    }
    p.finalists.resize(a.get<int32_t>());
    for (PartWork::Finalist& f : p.finalists) {
      f.graph = a.getString();
      f.category = a.getString();
      f.vote = a.get<double>();
      f.loss = a.get<double>();
      f.seconds = a.get<double>();
      f.fitLoss = a.get<double>();
      f.pixelRmse = a.get<double>();
      f.contrast = a.get<double>();
      f.coarseContrast = a.get<double>();
      f.chroma = a.get<double>();
      f.chromaOutside = a.get<double>();
      f.qualifies = a.get<uint8_t>() != 0;
    }
    p.photoContrast = a.get<double>();
    p.photoCoarseContrast = a.get<double>();
    p.photoChroma = a.get<double>();
    p.heldOut = a.get<uint8_t>() != 0;
    p.startValues = a.getVector<float>();
    p.startUv.rotation = a.get<float>();
    p.startUv.logScale = a.get<float>();
    p.startUv.offset.x() = a.get<float>();
    p.startUv.offset.y() = a.get<float>();
    if (p.category == "homogeneous") p.mode = PartMode::Homogeneous;
    return true;
  }
  void finish(Context&, const Reads&) override { bank_.reset(); }  // not needed after

 private:
  std::unique_ptr<ExemplarBank> bank_;  ///< built or loaded for the first part that needs it
};

}  // namespace

std::unique_ptr<Stage> makeSelectStage() {
  return std::make_unique<SelectStage>();
}

}  // namespace ps::pipeline
