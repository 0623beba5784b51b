#pragma once
// The CPU time the process has used (all its threads), as a std::chrono clock. For the tests that
// bound how soon a cancellation is honoured: CPU time counts the work done after the cancel,
// which other processes on a loaded machine (ctest -j, a shared CI host) do not stretch as they
// stretch wall time. Work that several threads finish in parallel counts once per thread.
#include <time.h>

#include <chrono>

namespace motionmap::test {

struct CpuClock {
  using duration = std::chrono::nanoseconds;
  using rep = duration::rep;
  using period = duration::period;
  using time_point = std::chrono::time_point<CpuClock>;
  static constexpr bool is_steady = true;

  static time_point now() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return time_point(std::chrono::seconds(t.tv_sec) + std::chrono::nanoseconds(t.tv_nsec));
  }
};

}  // namespace motionmap::test
