// Fuzz entry points: each feeds raw bytes to one of the readers that take files from users.
// A reader may accept the bytes or refuse them with ps::InputError; anything else (another
// exception, a crash, a sanitizer report, a hang) is a finding. The same entries replay the seed
// corpora and every kept crash in the normal test run (test_fuzz_replay.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ps::fuzz {

/// "scene_json", "obj", "label_image", "graph_json" (the last only when the graph module is built).
std::vector<std::string> targets();

/// Runs one target on the bytes. Returns true when the reader accepted them, false when it
/// refused them with ps::InputError; lets any other exception escape.
bool run(const std::string& target, const uint8_t* data, size_t size);

}  // namespace ps::fuzz
