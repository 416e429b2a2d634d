#include "fuzz_entries.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "photoscene/core/error.hpp"
#include "photoscene/core/log.hpp"
#include "photoscene/io.hpp"
#if PS_HAVE_GRAPH
#include "photoscene/graph.hpp"
#endif

namespace ps::fuzz {

namespace fs = std::filesystem;

namespace {
/// A per-process scratch folder (removed at exit) holding the bytes as a file.
fs::path scratchFile(const std::string& name, const uint8_t* data, size_t size) {
  static io::TempDir dir("photoscene-fuzz");
  const fs::path p = dir / name;
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return p;
}
}  // namespace

std::vector<std::string> targets() {
  std::vector<std::string> t = {"scene_json", "obj", "label_image"};
#if PS_HAVE_GRAPH
  t.push_back("graph_json");
#endif
  return t;
}

bool run(const std::string& target, const uint8_t* data, size_t size) {
  static const bool quiet = [] {  // warnings about unknown keys would drown the fuzzer's output
    initLogging(LogLevel::Error);
    return true;
  }();
  (void)quiet;
  try {
    if (target == "scene_json") {
      io::readSceneJson(scratchFile("scene.json", data, size));
    } else if (target == "obj") {
      io::readObj(scratchFile("mesh.obj", data, size));
    } else if (target == "label_image") {
      io::readLabelImage(scratchFile("labels.png", data, size));
#if PS_HAVE_GRAPH
    } else if (target == "graph_json") {
      MaterialGraph g = MaterialGraph::fromString(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
      g.evaluate(8, MapSet::all());
#endif
    } else {
      PS_Check(false, "unknown fuzz target " << target);
    }
    return true;
  } catch (const InputError&) {
    return false;
  }
}

}  // namespace ps::fuzz
