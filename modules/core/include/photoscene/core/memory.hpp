// Peak memory of the process, for the run log and metrics.json (issue 9: resource limits).
#pragma once

#include <cstdint>

namespace ps {

/// The process's peak resident set size so far, in bytes (getrusage's ru_maxrss; 0 where the
/// platform does not report it). Monotonic: the peak of the whole run up to the call.
int64_t peakMemoryBytes();

/// peakMemoryBytes() in MiB.
double peakMemoryMiB();

}  // namespace ps
