// ps::GraphLibrary: loads a folder of graph files.
#include "photoscene/graph/graph_library.hpp"

#include "photoscene/core.hpp"
#include "photoscene/core/data_folder.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#ifndef PS_GRAPH_LIBRARY_DIR
#define PS_GRAPH_LIBRARY_DIR ""
#endif

namespace ps {

std::string GraphLibrary::defaultFolder() {
  if (const char* env = std::getenv("PHOTOSCENE_GRAPH_LIBRARY"); env && *env) return env;
  // an installed tree's share/photoscene/graphs, else the source tree's (ps::findDataFolder)
  if (const auto found = findDataFolder("graphs", PS_GRAPH_LIBRARY_DIR); !found.empty())
    return found.string();
  return PS_GRAPH_LIBRARY_DIR;
}

GraphLibrary GraphLibrary::load(const std::string& folder) {
  namespace fs = std::filesystem;
  GraphLibrary lib;
  lib.folder_ = folder.empty() ? defaultFolder() : folder;
  std::error_code ec;
  if (!fs::is_directory(lib.folder_, ec))
    throw InputError(lib.folder_, "", "expected a folder of graph *.json files (set "
                                      "PHOTOSCENE_GRAPH_LIBRARY or pass a folder)");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(lib.folder_))
    if (e.is_regular_file() && e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError(lib.folder_, "", "expected at least one graph *.json file");
  for (const auto& f : files) {
    auto g = std::make_shared<MaterialGraph>(MaterialGraph::fromFile(f.string()));
    if (lib.contains(g->name()))
      throw InputError(f.string(), "name", "duplicate graph name \"" + g->name() + "\"");
    lib.graphs_.push_back(g);
    std::sort(lib.graphs_.begin(), lib.graphs_.end(),
              [](const auto& a, const auto& b) { return a->name() < b->name(); });
  }
  spdlog::debug("graph library {}: {} graphs", lib.folder_, lib.graphs_.size());
  return lib;
}

std::vector<std::string> GraphLibrary::names() const {
  std::vector<std::string> n;
  for (const auto& g : graphs_) n.push_back(g->name());
  return n;
}

bool GraphLibrary::contains(const std::string& name) const {
  for (const auto& g : graphs_)
    if (g->name() == name) return true;
  return false;
}

const MaterialGraph& GraphLibrary::get(const std::string& name) const {
  for (const auto& g : graphs_)
    if (g->name() == name) return *g;
  throw InputError(folder_, name, "expected the name of a graph in the library (see `photoscene graphs --list`)");
}

std::vector<std::string> GraphLibrary::namesInCategory(const std::string& category) const {
  std::vector<std::string> n;
  for (const auto& g : graphs_)
    if (g->category() == category) n.push_back(g->name());
  return n;
}

uint64_t GraphLibrary::contentHash() const {
  Hasher h;
  for (const auto& g : graphs_) h.add(g->contentHash());
  return h.digest();
}

}  // namespace ps
