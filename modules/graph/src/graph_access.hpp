// Private: access to a MaterialGraph's parsed spec (for gradient checks).
#pragma once

#include "engine.hpp"

namespace ps {
struct GraphAccess {
  static std::shared_ptr<const graphimpl::GraphSpec> spec(const MaterialGraph& g);
};
}  // namespace ps
