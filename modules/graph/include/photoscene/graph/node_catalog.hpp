// The node types a graph file may use (the catalog is also printed in modules/graph/FORMAT.md).
//
// Every node type is tileable (periodic on the unit square), resolution independent (spatial
// parameters are in texture units, not pixels), and comes as a forward and an analytic backward
// kernel sharing one context (nvdiffrast style).
#pragma once

#include "photoscene/graph/material_graph.hpp"

#include <string>
#include <vector>

namespace ps {

/// An image port of a node type.
struct NodePort {
  std::string name;
  /// 1 (gray, CV_32FC1), 3 (color, CV_32FC3), or 0 ("any": the node's working channel count,
  /// the largest among its "any" inputs; a gray image is broadcast where color is expected).
  int channels = 1;
  bool optional = false;
};

/// Description of one node type.
struct NodeTypeDesc {
  std::string name;
  std::string doc;
  std::vector<NodePort> inputs, outputs;
  std::vector<GraphParameter> params;  ///< offsets index the node's own flat parameter vector
};

/// All node types, sorted by name.
std::vector<NodeTypeDesc> nodeCatalog();

}  // namespace ps
