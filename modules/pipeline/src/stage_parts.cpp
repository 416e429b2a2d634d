// Stage `parts`: what each part gets (fitted, fixed, skipped, emitter, window), from scene.json.
// Cheap, so it is derived again on every run; its key still reaches every stage after it.
#include <algorithm>

#include "stages.hpp"

namespace ps::pipeline {

namespace {

class PartsStage : public DerivedStage {
 public:
  PartsStage() : DerivedStage("parts", Unit::Part) {
    decl.scene = {"geometry", "parts.{}.skip", "parts.{}.fixed", "lights.area[].part",
                  "lights.environment.window_parts"};
    decl.writes = {"PartWork::mode", "PartWork::skipped", "PartWork: the fixed material"};
  }

  bool compute(Context& ctx, const Reads& in, int u) override {
    PartWork& p = ctx.parts[u];
    const std::vector<int> emitters = in.emitterParts(), windows = in.windowParts();
    const bool emitter = std::find(emitters.begin(), emitters.end(), u) != emitters.end();
    const bool window = std::find(windows.begin(), windows.end(), u) != windows.end();
    if (emitter) {
      p.mode = PartMode::Emitter;
      p.skipped = "emitter";
    } else if (window) {
      p.mode = PartMode::Window;
      p.skipped = "window (an opening onto the environment)";
    } else if (in.partSkip(u)) {
      p.mode = PartMode::Skip;
      p.skipped = "skip (scene.json)";
    } else if (const auto& f = in.partFixed(u)) {
      p.mode = PartMode::Fixed;
      p.skipped = "fixed (scene.json)";
      p.albedo = f->albedo.cast<float>();
      p.roughness = static_cast<float>(f->roughness);
      p.metallic = static_cast<float>(f->metallic);
      p.specular = static_cast<float>(f->specular);
    }
    return true;
  }
};

}  // namespace

std::unique_ptr<Stage> makePartsStage() {
  return std::make_unique<PartsStage>();
}

}  // namespace ps::pipeline
