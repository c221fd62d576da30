// CPU time of the whole process so far, every thread's (llvmpipe rasterises on threads of its own, the
// decoders run on theirs): the cost of work when wall time depends on what else the machine runs.
// Thread contract: any thread.
#pragma once

#include <ctime>

namespace th {

inline double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace th
