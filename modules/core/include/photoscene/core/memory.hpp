// Peak memory of the process, for the run log and metrics.json (issue 9: resource limits), and the
// allocator setting for programs that allocate many large images.
#pragma once

#include <cstdint>

namespace ps {

/// The process's peak resident set size so far, in bytes (getrusage's ru_maxrss; 0 where the
/// platform does not report it). Monotonic: the peak of the whole run up to the call.
int64_t peakMemoryBytes();

/// peakMemoryBytes() in MiB.
double peakMemoryMiB();

/// Lets the C library reuse freed image buffers up to 32 MiB (a 1024 x 1024 RGB float map is
/// 12 MiB) instead of returning each to the system and faulting fresh zeroed pages in on the next
/// allocation: glibc maps every block above its dynamic threshold (128 KiB at first) on its own.
/// A graph evaluation at 1024 px allocates its nodes' maps anew, so the library's 1024 px sweep
/// spent half its time in the kernel (Graph_Library tests: 31 s -> 16 s, sys 15.8 s -> 0.7 s).
/// Freed memory above 256 MiB is still returned. For programs (main), not libraries: it sets
/// process-wide allocator policy. No effect where the C library is not glibc.
void reuseFreedImageMemory();

}  // namespace ps
