#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.
// Switch for the floating-point shortcuts of the spline analysis and the
// report (bezierize/analyze.cpp, report/report.cpp): error-bounded and
// exactness-tracked doubles (numeric/tracked.hpp) and certified float root
// isolation, each falling back to exact rationals where it cannot decide.
// They are on by default; turning them off sends every decision they make to
// the exact rational path, which is what the tests compare them with
// (tests/bezierize/fast_path_test.cpp). Process-wide; meant for tests and
// benchmarks, not for switching while analyses run on other threads.
namespace cmr {

/// Whether the floating-point shortcuts are used (default true).
bool fast_paths_enabled();
void set_fast_paths_enabled(bool on);

/// Turns the shortcuts off for its lifetime (tests).
class ExactOnlyScope {
 public:
  ExactOnlyScope() : was_(fast_paths_enabled()) { set_fast_paths_enabled(false); }
  ~ExactOnlyScope() { set_fast_paths_enabled(was_); }
  ExactOnlyScope(const ExactOnlyScope&) = delete;
  ExactOnlyScope& operator=(const ExactOnlyScope&) = delete;

 private:
  bool was_;
};

}  // namespace cmr
