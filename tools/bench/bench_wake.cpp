// How late the worker pool's other threads join a batch (spline/parallel.hpp,
// WorkerPool): for each idle gap before a batch, the time from the call to
// run() until a job first starts on a thread other than the caller's. A
// batch is 64 jobs of 10 µs of spinning each (640 µs on one thread, the size
// of a 512² region render's block jobs on this project's VM), so "never"
// means the caller ran all of them before any worker arrived.
//
// Usage: bench_wake [BATCHES] — prints median, 10th and 90th percentile per
// gap, and the CPU time an idle pool uses in the 100 ms after a batch
// (docs/performance.md, "An idle core joins late").
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>

#include "spline/parallel.hpp"

namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kJobs = 64;
constexpr auto kJob = std::chrono::microseconds(10);
constexpr double kNever = std::numeric_limits<double>::infinity();

/// Microseconds until a worker other than the caller started a job of the
/// batch; infinity when none did (so "never" sorts last).
double first_worker_start() {
  const Clock::time_point t0 = Clock::now();
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<long long> first_ns{-1};
  cmr::WorkerPool::shared().run(kJobs, 0, [&](std::size_t) {
    if (std::this_thread::get_id() != caller) {
      long long none = -1;
      first_ns.compare_exchange_strong(
          none, std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count());
    }
    for (const Clock::time_point s = Clock::now(); Clock::now() - s < kJob;) {
    }
  });
  return first_ns < 0 ? kNever : static_cast<double>(first_ns) / 1000.0;
}

/// Seconds of CPU time this process has used (every thread).
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

std::string shown(double us) {
  char b[32];
  if (std::isinf(us)) return "never";
  std::snprintf(b, sizeof b, "%.1f us", us);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  const int batches = argc > 1 ? std::max(10, std::atoi(argv[1])) : 200;
  std::printf("worker pool: %u hardware threads, %zu jobs of 10 us a batch, %d batches a gap\n",
              std::thread::hardware_concurrency(), kJobs, batches);
  std::printf("  %-10s %12s %12s %12s %8s  (first job on another thread)\n", "idle gap", "median", "p10", "p90",
              "never");
  for (const int gap_us : {0, 100, 1000, 5000, 20000}) {
    std::vector<double> late;
    for (int b = 0; b < batches; ++b) {
      std::this_thread::sleep_for(std::chrono::microseconds(gap_us));
      late.push_back(first_worker_start());
    }
    std::sort(late.begin(), late.end());
    const auto at = [&](double q) { return shown(late[static_cast<std::size_t>(q * (late.size() - 1))]); };
    const auto never = std::count(late.begin(), late.end(), kNever);
    std::printf("  %7.1f ms %12s %12s %12s %7.0f%%\n", gap_us / 1000.0, at(0.5).c_str(), at(0.1).c_str(),
                at(0.9).c_str(), 100.0 * static_cast<double>(never) / static_cast<double>(late.size()));
  }
  // What a worker's waiting costs: CPU time over 100 ms after a batch, with
  // nothing to do.
  (void)first_worker_start();
  const double c0 = cpu_seconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  std::printf("  idle after a batch: %.2f ms of CPU in the next 100 ms\n", 1e3 * (cpu_seconds() - c0));
  return 0;
}
