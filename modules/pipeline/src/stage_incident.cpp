// Stages `incident0` and `incident1`: per view, the 8 x 16 incident-light grids (raytrace's
// computeIncidentLight) under the lights of the same round and its materials (neutral, then
// fitted); the render layer reads them in the fit and the refine.
#include <algorithm>

#include <fmt/format.h>
#include "photoscene/core/log.hpp"

#include "archive_io.hpp"
#include "stages.hpp"

namespace ps::pipeline {

namespace {

class IncidentStage : public Stage {
 public:
  explicit IncidentStage(int round)
      : Stage(round == 0 ? "incident0" : "incident1", Unit::View), round_(round) {
    decl.scene = {"geometry", "up", "lights", "views[].camera", "parts.{}.fixed", "options.seed"};
    decl.options = {"preset", "work_width", "baseline", "fit_views", "incident"};
    decl.after = {"parts", "geometry", "observe", "pin", "lights0"};
    if (round == 1) {
      decl.options.push_back("library");
      decl.after.insert(decl.after.end(), {"select", "fit", "refine0", "lights1"});
    }
    // 2: grid points only on the parts fitted in the view; 3: paths from a grid point get one
    // bounce fewer (the point's own scatter is the first; raytrace/incident_light.cpp); 4: the
    // direct light can also be sampled from the lights, combined by MIS
    // (IncidentLightOptions::directSamples; PresetBudget::incidentDirectSamples, 0 for now);
    // 5: round 1 records what each point's light owes to each part's albedo (stage_bounce.cpp);
    // 6: round 1 samples the lamps (PresetBudget::incident1DirectSamples)
    decl.version = 6;
    decl.writes = {"ViewWork::grid"};
    if (round == 1) decl.writes.push_back("PartWork::gridAlbedo");
  }

  bool compute(Context& ctx, const Reads& in, int v) override {
    if (!tracer_) {
      materials_ = round_ == 1 ? fittedMaterials(ctx, in, in.fitOptions().mapSize)
                               : neutralMaterials(ctx, in);
      tracer_ = std::make_unique<PathTracer>(in.litScene(), materials_);
    }
    IncidentLightOptions o;
    o.stride = in.budget().incidentStride;
    o.samplesPerBin = in.incidentSamples();
    o.directSamples = in.incidentDirectSamples(round_);
    o.render.seed = in.seed() + 101 * v;
    o.albedoSensitivity = round_ == 1;
    // only the parts fitted in this view read its grid (fit, refine, baselines)
    o.parts.assign(in.litScene().parts.size(), 0);
    int fitted = 0;
    const bool pixelMedian = in.baseline() == Baseline::PixelMedian;  // reads no grid
    const bool allViews = in.fitAllViews();
    for (const PartWork& p : ctx.parts) {
      const std::vector<int> views = fitViews(p, allViews);
      if (!pixelMedian && ((p.mode == PartMode::Fit || p.mode == PartMode::Homogeneous) &&
                           std::find(views.begin(), views.end(), v) != views.end() &&
                           p.id >= 0 && p.id < static_cast<int>(o.parts.size()))) {
        o.parts[p.id] = 1;
        ++fitted;
      }
    }
    const GBuffer& gb = ctx.views[v].gbuffer;
    ctx.views[v].grid = computeIncidentLight(*tracer_, gb, in.camera(v), o);
    const IncidentLightGrid& g = ctx.views[v].grid;
    int surface = 0, traced = 0;
    for (int gy = 0; gy < g.height; ++gy)
      for (int gx = 0; gx < g.width; ++gx) {
        surface +=
            gb.partId.at<int>(g.pixelY(gy, gb.partId.rows), g.pixelX(gx, gb.partId.cols)) >= 0;
        traced += g.valid[static_cast<size_t>(gy) * g.width + gx];
      }
    if (traced < surface)
      spdlog::info("{}: view {}: {} of {} grid points traced, {} skipped: {}", decl.name, v, traced,
                   surface, surface - traced,
                   pixelMedian
                       ? std::string("the pixel-median baseline reads no grid")
                       : fmt::format("no part fitted in this view there ({} parts are; windows, "
                                     "emitters, fixed parts and parts fitted in other views read "
                                     "no grid of this view)",
                                     fitted));
    return true;
  }
  void save(const Context& ctx, int v, Archive& a) const override { putGrid(a, ctx.views[v].grid); }
  bool load(Context& ctx, const Reads&, int v, Archive& a) override {
    ctx.views[v].grid = getGrid(a);
    return true;
  }
  void finish(Context& ctx, const Reads& in) override {
    tracer_.reset();  // the tracer and maps are not needed after
    materials_.clear();
    // the albedos the grids' bounced light comes from (the parts hold refine0's results here)
    if (round_ == 1)
      for (PartWork& p : ctx.parts)
        if (p.mode == PartMode::Fit || p.mode == PartMode::Homogeneous)
          p.gridAlbedo = meanAlbedo(ctx, in, p);
  }

 private:
  int round_;
  std::vector<PartMaterial> materials_;
  std::unique_ptr<PathTracer> tracer_;  ///< built for the first view that misses the cache
};

}  // namespace

std::unique_ptr<Stage> makeIncidentStage(int round) {
  return std::make_unique<IncidentStage>(round);
}

}  // namespace ps::pipeline
