// Where the pipeline tests find the bundled sample scene (samples/data/living-room).
#pragma once

#include <filesystem>

namespace ps::test {

/// The bundled sample: scene.json, the coarse room.obj, the exact room_exact.obj and gt/twin.
inline const std::filesystem::path kSample =
    std::filesystem::path(PS_SOURCE_DIR) / "samples/data/living-room";

}  // namespace ps::test
