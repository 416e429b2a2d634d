// The library of material graphs: a folder of *.json graph files found at run time.
//
// Where: the `folder` argument if not empty, else the environment variable
// PHOTOSCENE_GRAPH_LIBRARY, else share/photoscene/graphs of an installed tree found next to the
// running program, else the folder compiled in (modules/graph/library of the source tree), else
// share/photoscene/graphs under the configured install prefix (ps::findDataFolder). A user adds a
// graph by dropping a JSON file (format: modules/graph/FORMAT.md) into the folder; no recompiling.
#pragma once

#include "photoscene/graph/material_graph.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ps {

/// The categories of spec section 4; every graph belongs to exactly one.
const std::vector<std::string>& materialCategories();

class GraphLibrary {
 public:
  /// The folder load("") reads: $PHOTOSCENE_GRAPH_LIBRARY, else the installed or source-tree
  /// library (see above).
  static std::string defaultFolder();
  /// Loads and validates every *.json in `folder` (sorted by file name). Throws ps::InputError
  /// for a missing folder, a malformed graph, an unknown category or a duplicate name.
  static GraphLibrary load(const std::string& folder = "");

  const std::string& folder() const { return folder_; }
  /// Graph names, sorted.
  std::vector<std::string> names() const;
  int size() const { return static_cast<int>(graphs_.size()); }
  bool contains(const std::string& name) const;
  /// The graph as loaded (default values); throws ps::InputError for an unknown name.
  const MaterialGraph& get(const std::string& name) const;
  /// A fresh, independent copy of the graph `name` (default values, empty caches).
  MaterialGraph create(const std::string& name) const { return get(name).clone(); }
  /// Names of the graphs of one category.
  std::vector<std::string> namesInCategory(const std::string& category) const;
  /// Hash of every graph's content (for caches of exemplar banks and fits).
  uint64_t contentHash() const;

 private:
  std::string folder_;
  std::vector<std::shared_ptr<MaterialGraph>> graphs_;  // sorted by name
};

}  // namespace ps
