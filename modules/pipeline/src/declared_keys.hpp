// The inputs a stage declares (stage.hpp), as the runner hashes them into the stage's cache key
// (private to the module).
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "photoscene/core/rng.hpp"
#include "stage.hpp"

namespace ps::pipeline {

/// The JSON pointers a declared scene.json key stands for, for one unit (stage.hpp: `[]` and
/// `{}` wildcards, `views[]` bound for per-view units and `parts.{}` for per-part units). A key
/// absent from the file still stands for its pointer (adding it changes the key).
std::vector<nlohmann::json::json_pointer> expandKey(const nlohmann::json& scene,
                                                    std::string_view key, Unit unit, int view,
                                                    const std::string& part);
/// Whether the declared key `declared` covers `key` (the same key or one of its parents).
bool keyCovers(std::string_view declared, std::string_view key);
/// Whether a scene.json position holds a file path whose bytes stand for it (`geometry`,
/// `views/<i>/image`, `views/<i>/segments`, `lights/environment/image`).
bool isFileKey(const nlohmann::json::json_pointer& at);

/// Adds every input `decl` declares for one unit to `h`: each declared scene.json key's value as
/// written, a file-valued key by its file's bytes (`fileHashes` remembers them by path), each
/// option's value and each declared file of the output folder by its bytes.
void hashDeclaredInputs(Hasher& h, const RunInputs& in, const StageDecl& decl, int unit,
                        const std::string& part, std::map<std::string, uint64_t>& fileHashes);

}  // namespace ps::pipeline
