// Stages `refine0` and `refine1` (one row, `refine`): per part, in parallel, the second round of
// the paper: homogeneous parts fitted again in closed form, textured parts get one albedo scale,
// a per-channel offset and a roughness factor (optim's fitHomogeneous / refineTextured). Round 0
// runs under the first lights, so that a part whose fit missed its mean does not bend the global
// light solve; round 1 under the lights and grids of the fitted materials.
#include "photoscene/core.hpp"
#include "stages.hpp"

namespace ps::pipeline {

namespace {

class RefineStage : public Stage {
 public:
  explicit RefineStage(int round) : Stage(round == 0 ? "refine0" : "refine1", Unit::Part) {
    decl.record = "refine";
    decl.scene = {"views[].camera", "views[].image", "views[].color_space"};
    decl.options = {"preset", "library", "work_width", "fit_views"};
    decl.after = {"geometry", "align", "observe",
                  "select",   "fit",   round == 0 ? "incident0" : "incident1"};
    decl.writes = {
        "PartWork: albedoScale, albedoOffset, roughnessFactor, refineLoss; homogeneous albedo, "
        "roughness"};
    decl.parallel = true;
    // 2: the photo divided by its view's exposure; 3: a homogeneous part's roughness from highlights
    // only, else the prior's centre (HomogeneousRoughness); 4: the albedo (homogeneous) or the
    // offsets (textured) match the photo's mean with the render clipped where an integer-coded
    // photo clips (PartView::clip)
    decl.version = 4;
  }

  bool applies(const Context& ctx, int u) const override {
    return ctx.parts[u].mode == PartMode::Fit || ctx.parts[u].mode == PartMode::Homogeneous;
  }

  bool compute(Context& ctx, const Reads& in, int u) override {
    PartWork& p = ctx.parts[u];
    const ViewWork& view = ctx.views[p.view];
    // the photo as the render sees it: divided by the view's exposure (lights0's, or lights1's)
    const cv::Mat photo = partPhoto(in.photo(p.view), view, p.id) / ctx.viewExposure(p.view);
    const cv::Mat& mask = view.fitMask.at(p.id);
    const PartGeometry geo = preparePartGeometry(
        view.gbuffer, in.camera(p.view).position().cast<float>(), view.grid, mask, p.id);
    const int candidates = in.budget().refineCandidates;
    if (p.mode == PartMode::Homogeneous) {
      // the albedo (per channel, closed form) and roughness again under the new lights
      const HomogeneousFit f = fitHomogeneousPart(ctx, in, p, geo, photo, candidates);
      p.albedo = f.albedo;
      p.roughness = f.roughness;
      p.refineLoss = f.loss;
    } else {
      // only one albedo scale, its offset and the roughness factor (the maps keep their pattern)
      MaterialGraph g = in.library().create(p.graph);
      g.setValues(p.values);
      const MaterialMaps maps =
          g.evaluate(in.fitOptions().mapSize, MapSet::of({MapKind::Albedo, MapKind::Normal}));
      const TexturedRefine r =
          refineTextured(geo, photo, mask, maps.albedo, maps.normal, p.uv, p.roughness, candidates,
                         in.photoClip(p.view, ctx.viewExposure(p.view)));
      p.albedoScale = r.albedoScale;
      p.albedoOffset = r.albedoOffset;
      p.roughnessFactor = r.roughnessFactor;
      p.refineLoss = r.loss;
    }
    return true;
  }
  void save(const Context& ctx, int u, Archive& a) const override {
    const PartWork& p = ctx.parts[u];
    a.put(p.albedoScale);
    for (int k = 0; k < 3; ++k) a.put(p.albedoOffset[k]);
    a.put(p.roughnessFactor);
    for (int k = 0; k < 3; ++k) a.put(p.albedo[k]);
    a.put(p.roughness);
    a.put(p.refineLoss);
  }
  bool load(Context& ctx, const Reads&, int u, Archive& a) override {
    PartWork& p = ctx.parts[u];
    p.albedoScale = a.get<float>();
    for (int k = 0; k < 3; ++k) p.albedoOffset[k] = a.get<float>();
    p.roughnessFactor = a.get<float>();
    for (int k = 0; k < 3; ++k) p.albedo[k] = a.get<float>();
    p.roughness = a.get<float>();
    p.refineLoss = a.get<double>();
    return true;
  }
};

}  // namespace

std::unique_ptr<Stage> makeRefineStage(int round) {
  return std::make_unique<RefineStage>(round);
}

}  // namespace ps::pipeline
