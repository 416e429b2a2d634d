// Stage `baseline-<name>`: the paper's baselines instead of select, fit and refine, under lights0
// (the lighting both start from): every fitted part gets a homogeneous albedo, roughness 0.7;
// pixel-median: the photo's median colour (times the scale pin); shading-median: the median of
// photo / diffuse shading (optim's shadingMedianAlbedo).
#include "stages.hpp"

namespace ps::pipeline {

namespace {

class BaselineStage : public Stage {
 public:
  explicit BaselineStage(Baseline baseline)
      : Stage(std::string("baseline-") + baselineName(baseline), Unit::Part) {
    decl.scene = {"views[].camera", "views[].image", "views[].color_space"};
    decl.options = {"baseline", "work_width"};
    decl.after = {"geometry", "align", "observe", "pin", "incident0"};
    decl.writes = {"PartWork: albedo, roughness 0.7, PartMode::Homogeneous"};
  }

  bool applies(const Context& ctx, int u) const override {
    return ctx.parts[u].mode == PartMode::Fit || ctx.parts[u].mode == PartMode::Homogeneous;
  }

  bool compute(Context& ctx, const Reads& in, int u) override {
    PartWork& p = ctx.parts[u];
    if (in.baseline() == Baseline::PixelMedian) {
      p.albedo = (p.median * ctx.albedoPin).cwiseMin(1.0f);
    } else {
      const ViewWork& view = ctx.views[p.view];
      const PartGeometry geo =
          preparePartGeometry(view.gbuffer, in.camera(p.view).position().cast<float>(), view.grid,
                              view.fitMask.at(p.id), p.id);
      p.albedo = shadingMedianAlbedo(
          geo, partPhoto(in.photo(p.view), view, p.id) / ctx.viewExposure(p.view));
    }
    setHomogeneous(p);
    return true;
  }
  void save(const Context& ctx, int u, Archive& a) const override {
    for (int k = 0; k < 3; ++k) a.put(ctx.parts[u].albedo[k]);
  }
  bool load(Context& ctx, const Reads&, int u, Archive& a) override {
    PartWork& p = ctx.parts[u];
    for (int k = 0; k < 3; ++k) p.albedo[k] = a.get<float>();
    setHomogeneous(p);
    return true;
  }

 private:
  static void setHomogeneous(PartWork& p) {
    p.mode = PartMode::Homogeneous;
    p.graph = p.category = "homogeneous";
    p.roughness = 0.7f;
    p.values.clear();
    p.skipped.clear();
  }
};

}  // namespace

std::unique_ptr<Stage> makeBaselineStage(Baseline baseline) {
  return std::make_unique<BaselineStage>(baseline);
}

}  // namespace ps::pipeline
