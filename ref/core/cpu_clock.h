// Thread CPU time in milliseconds (CLOCK_THREAD_CPUTIME_ID). Module and stage timings use it:
// the run is single-threaded, so it measures the work done and not the load of the machine.
// Timings go to run.json only, never into results or traces.
#pragma once
#include <ctime>

namespace dynref {

inline double ClockMs(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

inline double ThreadCpuMs() { return ClockMs(CLOCK_THREAD_CPUTIME_ID); }

// Wall-clock milliseconds (CLOCK_MONOTONIC): module timings of a run with --threads > 1, where
// the thread's CPU clock would miss the work of its helper threads.
inline double WallMs() { return ClockMs(CLOCK_MONOTONIC); }

}  // namespace dynref
