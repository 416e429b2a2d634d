// Stage `poses`: each piece of furniture (an OBJ object) moved onto the parts the views' pinned
// labels give it (align's fitObjectPoses); every later stage and the twin see the moved mesh.
#include <fmt/format.h>
#include "photoscene/core/log.hpp"

#include "archive_io.hpp"
#include "stages.hpp"

namespace ps::pipeline {

namespace {

class PosesStage : public Stage {
 public:
  PosesStage() : Stage("poses") {
    decl.scene = {"geometry",
                  "up",
                  "lights.area",
                  "lights.auto_ceiling_spacing",
                  "lights.environment.window_parts",
                  "views[].camera",
                  "views[].image",  // the labels are taken at the photo's working size
                  "views[].color_space",
                  "views[].segments",
                  "views[].segment_parts",
                  "options.refine_poses"};
    decl.options = {"work_width"};
    decl.writes = {"Context::poses", "the scene's mesh"};
  }

  bool compute(Context& ctx, const Reads& in, int) override {
    if (!in.refinePoses()) return false;
    const Scene& scene = in.sceneGeometry();
    std::vector<PoseLabels> views;
    for (int v = 0; v < in.viewCount(); ++v)
      if (!in.labels(v).empty())
        views.push_back({in.camera(v), pinnedPartLabels(in.labels(v), in.segmentParts(v))});
    std::vector<int> fixed = in.emitterParts();
    for (int p : in.windowParts()) fixed.push_back(p);
    const std::vector<int> objects = movableObjects(scene.mesh, scene.up, fixed);
    if (views.empty() || objects.empty()) {
      spdlog::info("poses: {}", views.empty() ? "no view has labels" : "no movable object");
      return false;
    }
    Mesh mesh = scene.mesh;  // the search moves its own copy; applyPoses the scene's
    std::vector<PoseFit> fits = fitObjectPoses(mesh, scene.up, objects, views);
    for (const PoseFit& f : fits)
      spdlog::info(
          "poses: {} {} (labelled pixels mislabelled by the render {} -> {}, {} own, {} tries)",
          scene.mesh.objectNames[f.object],
          f.pose.isIdentity()
              ? std::string("kept")
              : fmt::format("moved {:.1f} cm, turned {:.2f} deg, scaled {:.3f}",
                            100 * f.pose.shift.norm(), f.pose.yaw * 180 / M_PI, f.pose.scale),
          f.mismatchBefore, f.mismatchAfter, f.pixels, f.evaluations);
    ctx.applyPoses(std::move(fits));
    return true;
  }
  void save(const Context& ctx, int, Archive& a) const override {
    a.put<uint64_t>(ctx.poses.size());
    for (const PoseFit& f : ctx.poses) {
      a.put<int32_t>(f.object);
      putVec3s(a, {f.pose.pivot, f.pose.shift});
      a.put<float>(f.pose.yaw);
      a.put<float>(f.pose.scale);
      a.put<int32_t>(f.pixels);
      a.put<int32_t>(f.mismatchBefore);
      a.put<int32_t>(f.mismatchAfter);
      a.put<int32_t>(f.evaluations);
    }
  }
  bool load(Context& ctx, const Reads&, int, Archive& a) override {
    std::vector<PoseFit> fits(a.get<uint64_t>());
    for (PoseFit& f : fits) {
      f.object = a.get<int32_t>();
      const std::vector<Vec3f> v = getVec3s(a);
      f.pose.pivot = v.at(0);
      f.pose.shift = v.at(1);
      f.pose.yaw = a.get<float>();
      f.pose.scale = a.get<float>();
      f.pixels = a.get<int32_t>();
      f.mismatchBefore = a.get<int32_t>();
      f.mismatchAfter = a.get<int32_t>();
      f.evaluations = a.get<int32_t>();
    }
    ctx.applyPoses(std::move(fits));
    return true;
  }
};

}  // namespace

std::unique_ptr<Stage> makePosesStage() {
  return std::make_unique<PosesStage>();
}

}  // namespace ps::pipeline
