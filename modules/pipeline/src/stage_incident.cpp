// Stages `incident0` and `incident1`: per view, the 8 x 16 incident-light grids (raytrace's
// computeIncidentLight) under the lights of the same round and its materials (neutral, then
// fitted); the render layer reads them in the fit and the refine.
#include "archive_io.hpp"
#include "stages.hpp"

namespace ps::pipeline {

namespace {

class IncidentStage : public Stage {
 public:
  explicit IncidentStage(int round) : round_(round) {
    decl.name = round == 0 ? "incident0" : "incident1";
    decl.unit = Unit::View;
    decl.scene = {"geometry", "up", "lights", "views[].camera", "parts.{}.fixed", "options.seed"};
    decl.options = {"preset", "work_width"};
    decl.after = {"parts", "geometry", "observe", "pin", "lights0"};
    if (round == 1) {
      decl.options.push_back("library");
      decl.after.insert(decl.after.end(), {"select", "fit", "refine0", "lights1"});
    }
    decl.writes = {"ViewWork::grid"};
  }

  bool compute(Context& ctx, const Reads& in, int v) override {
    if (!tracer_) {
      materials_ = round_ == 1 ? fittedMaterials(ctx, in, in.fitOptions().mapSize)
                               : neutralMaterials(ctx, in);
      tracer_ = std::make_unique<PathTracer>(in.litScene(), materials_);
    }
    IncidentLightOptions o;
    o.stride = in.budget().incidentStride;
    o.samplesPerBin = in.budget().incidentSamples;
    o.render.seed = in.seed() + 101 * v;
    ctx.views[v].grid = computeIncidentLight(*tracer_, ctx.views[v].gbuffer, in.camera(v), o);
    return true;
  }
  void save(const Context& ctx, int v, Archive& a) const override { putGrid(a, ctx.views[v].grid); }
  bool load(Context& ctx, const Reads&, int v, Archive& a) override {
    ctx.views[v].grid = getGrid(a);
    return true;
  }
  void finish(Context&, const Reads&) override {  // the tracer and maps are not needed after
    tracer_.reset();
    materials_.clear();
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
