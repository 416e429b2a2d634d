// Where the pipeline tests find the bundled sample scene (samples/data/living-room), the
// exemplar bank they share, and the options of a quick run.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "photoscene/io/json.hpp"
#include "photoscene/pipeline.hpp"

namespace ps::test {

/// The bundled sample: scene.json, the coarse room.obj, the exact room_exact.obj and gt/twin.
inline const std::filesystem::path kSample =
    std::filesystem::path(PS_SOURCE_DIR) / "samples/data/living-room";

/// The exemplar bank's cache folder of this build tree: built by the first test that selects,
/// loaded by the others.
inline const std::filesystem::path kBankCache =
    std::filesystem::path(PS_BINARY_DIR) / "photoscene-cache";

/// The bundled sample's scene.json with its files named by absolute path (to be written elsewhere).
inline nlohmann::json sampleSceneJson() {
  nlohmann::json j = io::readJsonFile(kSample / "scene.json");
  j["geometry"] = (kSample / "room.obj").string();
  j["views"][0]["image"] = (kSample / "photos/view0.png").string();
  j["views"][0]["segments"] = (kSample / "segments/view0.png").string();
  return j;
}

/// A run of `scene` into `out` at preset fast with 128 px maps and the shared bank cache.
inline PipelineOptions sampleOptions(const std::filesystem::path& scene,
                                     const std::filesystem::path& out) {
  PipelineOptions o;
  o.scene = scene;
  o.out = out;
  o.preset = "fast";
  o.textureSize = 128;
  o.bankCache = kBankCache;
  return o;
}

}  // namespace ps::test
