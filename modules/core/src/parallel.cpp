#include "photoscene/core/parallel.hpp"

namespace ps {

int maxThreads() {
  return static_cast<int>(
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

ThreadLimit::ThreadLimit(int n) {
  if (n > 0)
    control_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                     static_cast<size_t>(n));
}

ThreadLimit::~ThreadLimit() = default;

}  // namespace ps
