// How late the worker pool's other threads join a batch, and how late the
// caller returns after its last job (spline/parallel.hpp, WorkerPool): for
// each idle gap before a batch, the time from the call to run() until a job
// first starts on a thread other than the caller's ("join"), and from the end
// of the batch's last job until run() returns ("tail"). A batch is 64 jobs of
// 10 µs of spinning each (640 µs on one thread, the size of a 512² region
// render's block jobs on this project's VM), so "never" means the caller ran
// all of them before any worker arrived. The second table announces each
// batch with WorkerPool::wake() 30 µs before run(), as a region render does
// before it clears its image.
//
// Usage: bench_wake [BATCHES] — prints median, 10th and 90th percentile per
// gap, and the CPU time an idle pool uses in the 100 ms after a batch and
// after a wake() with no batch (docs/performance.md, "An idle core joins late").
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
/// batch (join; infinity when none did, so "never" sorts last), and from the
/// end of the last job until run() returned (tail). With `announce`, the
/// batch is announced by wake() kPrepare before run().
struct Late {
  double join, tail;
};
constexpr auto kPrepare = std::chrono::microseconds(30);
void spin_for(std::chrono::microseconds d) {
  for (const Clock::time_point s = Clock::now(); Clock::now() - s < d;) {
  }
}
Late one_batch(bool announce) {
  if (announce) {
    cmr::WorkerPool::shared().wake();
    spin_for(kPrepare);
  }
  const Clock::time_point t0 = Clock::now();
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<long long> first_ns{-1}, last_end_ns{0};
  const auto since = [&] { return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count(); };
  cmr::WorkerPool::shared().run(kJobs, 0, [&](std::size_t) {
    if (std::this_thread::get_id() != caller) {
      long long none = -1;
      first_ns.compare_exchange_strong(none, since());
    }
    spin_for(kJob);
    const long long end = since();
    for (long long seen = last_end_ns; seen < end && !last_end_ns.compare_exchange_weak(seen, end);) {
    }
  });
  const double tail = static_cast<double>(since() - last_end_ns) / 1000.0;
  return {first_ns < 0 ? kNever : static_cast<double>(first_ns) / 1000.0, tail};
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

void table(int batches, bool announce) {
  std::printf("  %-10s %12s %12s %12s %8s %12s %12s  (%s)\n", "idle gap", "join median", "p10", "p90", "never",
              "tail median", "p90", announce ? "wake() 30 us before run()" : "run() alone");
  for (const int gap_us : {0, 100, 1000, 5000, 20000}) {
    std::vector<double> late, tail;
    for (int b = 0; b < batches; ++b) {
      std::this_thread::sleep_for(std::chrono::microseconds(gap_us));
      const Late l = one_batch(announce);
      late.push_back(l.join);
      tail.push_back(l.tail);
    }
    std::sort(late.begin(), late.end());
    std::sort(tail.begin(), tail.end());
    const auto at = [&](const std::vector<double>& v, double q) {
      return shown(v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))]);
    };
    const auto never = std::count(late.begin(), late.end(), kNever);
    std::printf("  %7.1f ms %12s %12s %12s %7.0f%% %12s %12s\n", gap_us / 1000.0, at(late, 0.5).c_str(),
                at(late, 0.1).c_str(), at(late, 0.9).c_str(),
                100.0 * static_cast<double>(never) / static_cast<double>(late.size()), at(tail, 0.5).c_str(),
                at(tail, 0.9).c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int batches = argc > 1 ? std::max(10, std::atoi(argv[1])) : 200;
  std::printf("worker pool: %u hardware threads, %zu jobs of 10 us a batch, %d batches a gap\n",
              std::thread::hardware_concurrency(), kJobs, batches);
  table(batches, false);
  table(batches, true);
  // What a worker's waiting costs: CPU time over 100 ms after a batch, and
  // after a wake() that no batch follows, with nothing to do.
  (void)one_batch(false);
  double c0 = cpu_seconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  std::printf("  idle after a batch: %.2f ms of CPU in the next 100 ms\n", 1e3 * (cpu_seconds() - c0));
  c0 = cpu_seconds();
  cmr::WorkerPool::shared().wake();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  std::printf("  a wake() with no batch: %.2f ms of CPU in the next 100 ms\n", 1e3 * (cpu_seconds() - c0));
  return 0;
}
