// Stage `geometry`: per view, the G-buffers of the coarse CAD at the working resolution
// (raytrace's renderGBuffer; the rectangle lights are geometry too).
#include "archive_io.hpp"
#include "stages.hpp"

namespace ps::pipeline {

namespace {

class GeometryStage : public Stage {
 public:
  GeometryStage() : Stage("geometry", Unit::View) {
    decl.scene = {"geometry", "up", "lights.area", "lights.auto_ceiling_spacing", "views[].camera"};
    decl.options = {"work_width"};
    decl.after = {"poses"};
    decl.writes = {"ViewWork::gbuffer"};
  }

  bool compute(Context& ctx, const Reads& in, int v) override {
    if (!tracer_) {
      const Scene& scene = in.sceneGeometry();
      tracer_ = std::make_unique<PathTracer>(scene, std::vector<PartMaterial>(scene.parts.size()));
    }
    ctx.views[v].gbuffer = renderGBuffer(*tracer_, in.camera(v));
    return true;
  }
  void save(const Context& ctx, int v, Archive& a) const override {
    putGBuffer(a, ctx.views[v].gbuffer);
  }
  bool load(Context& ctx, const Reads&, int v, Archive& a) override {
    ctx.views[v].gbuffer = getGBuffer(a);
    return true;
  }
  void finish(Context&, const Reads&) override { tracer_.reset(); }  // the BVH is not needed after

 private:
  std::unique_ptr<PathTracer> tracer_;  ///< gray materials: only what rays hit matters
};

}  // namespace

std::unique_ptr<Stage> makeGeometryStage() {
  return std::make_unique<GeometryStage>();
}

}  // namespace ps::pipeline
