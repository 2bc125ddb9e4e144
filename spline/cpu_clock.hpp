#pragma once
/// A time limit on the calling thread's CPU clock (CLOCK_THREAD_CPUTIME_ID),
/// for a search that runs on one thread and must end at the same place
/// whatever the machine's load: a loaded machine gives the thread fewer CPU
/// seconds per second of wall-clock time, not more or fewer evaluations per
/// CPU second. (The fix searches' guards were wall-clock: under load, Nimbus
/// Sans `S`'s glyph fix ran into its 9.5 s guard and found nothing.)
/// Reading the clock is a system call (about 0.6 µs on this project's VM,
/// against 27 ns for the wall clock), so passed() reads it on every
/// kStride-th call only. Not thread-safe: one per searching thread.
#include <time.h>

#include <algorithm>
#include <limits>

namespace cmr {

/// Seconds of CPU time the calling thread has used.
inline double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

class ThreadCpuDeadline {
 public:
  /// Never passes.
  ThreadCpuDeadline() = default;
  /// Passes once the calling thread has used `seconds` more CPU time.
  explicit ThreadCpuDeadline(double seconds) : end_(thread_cpu_seconds() + seconds), set_(true) {}
  bool passed() {
    if (!set_ || passed_) return passed_;
    if (++calls_ % kStride != 0) return false;
    passed_ = thread_cpu_seconds() > end_;
    return passed_;
  }
  /// Whether passed() has found the limit passed.
  bool found_passed() const { return passed_; }
  /// CPU seconds left (0 once passed; infinity when never).
  double left() const {
    if (!set_) return std::numeric_limits<double>::infinity();
    return passed_ ? 0.0 : std::max(0.0, end_ - thread_cpu_seconds());
  }
  static constexpr unsigned kStride = 16;

 private:
  double end_ = 0;
  bool set_ = false, passed_ = false;
  unsigned calls_ = 0;
};

}  // namespace cmr
