// Parallel loops over oneTBB.
//
// Determinism: parallelFor splits [begin, end) into fixed chunks of `grain` indices, so the body
// sees the same index ranges whatever the thread count; a body that writes only its own indices
// and draws randomness from Rng(seed).split(index) gives the same result on any thread count.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <cstdint>
#include <memory>

namespace ps {

/// Calls body(i) for every i in [begin, end), in parallel.
template <typename Body>
void parallelFor(int64_t begin, int64_t end, Body&& body, int64_t grain = 1) {
  if (end <= begin) return;
  tbb::parallel_for(
      tbb::blocked_range<int64_t>(begin, end, grain > 0 ? grain : 1),
      [&](const tbb::blocked_range<int64_t>& r) {
        for (int64_t i = r.begin(); i != r.end(); ++i) body(i);
      },
      tbb::simple_partitioner());
}

/// Calls body(rowBegin, rowEnd) over fixed chunks of `grain` rows, in parallel.
template <typename Body>
void parallelForRanges(int64_t begin, int64_t end, int64_t grain, Body&& body) {
  if (end <= begin) return;
  tbb::parallel_for(
      tbb::blocked_range<int64_t>(begin, end, grain > 0 ? grain : 1),
      [&](const tbb::blocked_range<int64_t>& r) { body(r.begin(), r.end()); },
      tbb::simple_partitioner());
}

/// The number of worker threads parallel loops may use now.
int maxThreads();

/// Limits parallel loops to n threads while alive (n <= 0: no limit). Apps hold one for --threads.
class ThreadLimit {
 public:
  explicit ThreadLimit(int n);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  std::unique_ptr<tbb::global_control> control_;
};

}  // namespace ps
