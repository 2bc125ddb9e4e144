// Growth benchmark (issue 23, items 4 and 5): how `cmr region`'s CPU backend
// (certified labels, no depth map, D = 12, fp64, every core) grows with
//   (a) the image size: 256^2 .. 2048^2, the uniform cubic B-spline of
//       examples/figures/fig8.json, point P3, default view;
//   (b) the degree: Bezier curves of degree 3..15 at 512^2, each a gentle
//       spiral (legs of length 1.08^i turning by -0.15 rad each, as
//       examples/bezier9.json), the middle point moved, default view;
//   (c) the span count: uniform cubic B-splines of 10 .. 10,000 spans at
//       512^2, the middle point moved, default view; two families: a seeded
//       random walk (its untouched spans fail, so every label is 0 without a
//       render: the row measures the setup), and a self-similar spiral
//       (legs growing by 0.1% and turning by 0.005 rad each: every span is
//       a similar copy of its neighbour, and the curvature is monotone: its
//       untouched spans pass, and the image has a region).
// Each row: the setup (RegionProblem::make; of it, the analysis of the spline
// before the move, backend::region_base, and the moved spans' preparation,
// backend::prepare_region with that analysis: Bezier points, exact piece
// polynomials), the render (CpuRegionBackend), Mp/s of the render, the share
// of pixels the exact path decided, and where the published method supports
// the scene (degrees 3..9, C2 joints) its best form (native per pixel or
// vectorised across 4 pixels, tools/bench/published_method.hpp) and cmr's
// ratio against it (setup excluded, as the baseline's setup is negligible).
// Best of N passes, each measurement stopping after kMeasureBudget seconds.
// Usage: bench_growth [repetitions=3] [tables=abc]   (run from the repository root)
#include <sys/utsname.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <thread>

#include "region/region.hpp"
#include "region/region_setup.hpp"
#include "spline/limits.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"
#include "tools/bench/published_method.hpp"
#include "tools/keep_freed_memory.hpp"

using namespace cmr;

namespace {

constexpr double kMeasureBudget = 2.0;  ///< seconds: no further passes of one measurement after this
constexpr int kDegreeSize = 512;        ///< image side of tables (b) and (c)

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// Seconds of CPU time this process (every thread) has used.
double cpu_now() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

double load_average() {
  double l = 0;
  std::ifstream("/proc/loadavg") >> l;
  return l;
}

/// Best wall-clock and best CPU seconds of f() over `reps` passes, or fewer
/// once they have taken kMeasureBudget seconds together (at least one).
struct Best {
  double wall = 1e300, cpu = 1e300;
};
template <class F>
Best best_of(int reps, F f) {
  Best b;
  double spent = 0;
  for (int r = 0; r < reps && spent < kMeasureBudget; ++r) {
    const double t0 = now(), c0 = cpu_now();
    f();
    const double t = now() - t0;
    b.wall = std::min(b.wall, t);
    b.cpu = std::min(b.cpu, cpu_now() - c0);
    spent += t;
  }
  return b;
}

/// A uniform double in [0, 1) from the generator's bits alone (the same
/// sequence on every standard library, unlike std::uniform_real_distribution).
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

/// Points of a polygon whose legs grow by `growth` and turn by `turn` each.
std::vector<Vec2> spiral_points(int count, double growth, double turn) {
  std::vector<Vec2> p{Vec2(0, 0)};
  double len = 1, angle = 0;
  for (int i = 1; i < count; ++i) {
    p.push_back(p.back() + len * Vec2(std::cos(angle), std::sin(angle)));
    len *= growth;
    angle += turn;
  }
  return p;
}

/// The degree-n Bezier of table (b): n+1 points on a gentle spiral.
BSpline spiral_bezier(int n) { return BSpline::bezier(spiral_points(n + 1, 1.08, -0.15), "spiral"); }

/// A uniform cubic B-spline (knots 0, 1, 2, ...) through `points` as control points.
BSpline uniform_cubic(std::vector<Vec2> points) {
  std::vector<double> knots;
  for (std::size_t i = 0; i < points.size() + 2; ++i) knots.push_back(static_cast<double>(i));
  return BSpline::make(3, std::move(knots), std::move(points));
}

/// Table (c), random walk: steps of length 0.5..1.5 in a direction that
/// turns by a uniform angle in [-0.6, 0.6) rad per step (seeded).
BSpline random_walk(int spans, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec2> p{Vec2(0, 0)};
  double angle = 0;
  for (int i = 1; i < spans + 3; ++i) {
    angle += 1.2 * unit(rng) - 0.6;
    p.push_back(p.back() + (0.5 + unit(rng)) * Vec2(std::cos(angle), std::sin(angle)));
  }
  return uniform_cubic(std::move(p));
}

/// Table (c), spiral: self-similar legs (growth 1.001, turn 0.005 rad).
BSpline spiral_spline(int spans) { return uniform_cubic(spiral_points(spans + 3, 1.001, 0.005)); }

RegionRequest request_of(int point, int size) {
  RegionRequest o;
  o.point = point;
  o.width = o.height = size;
  o.depth = false;  // label maps, as `cmr region` without --depth-map
  return o;
}

/// One row: setup (analysis + preparation), render, exact share, best baseline.
void row(const char* name, const BSpline& spline, int point, int size, int reps) {
  const RegionRequest o = request_of(point, size);
  std::shared_ptr<const backend::RegionBase> base;
  const Best t_base = best_of(reps, [&] { base = backend::region_base(spline, o.max_depth); });
  const Best t_prep = best_of(reps, [&] { (void)backend::prepare_region(spline, o, base); });
  std::optional<RegionProblem> problem;
  const Best t_make = best_of(reps, [&] { problem.emplace(RegionProblem::make(spline, o)); });
  CpuRegionBackend cpu;
  RegionResult img;
  const Best t_render = best_of(reps, [&] { img = cpu.render(*problem); });
  const double mpix = static_cast<double>(size) * size / 1e6;
  std::printf("  %-22s %5d %6d %9.4f %9.4f %9.4f %9.4f %8.2f %7.3f%%", name, spline.degree(), spline.segment_count(),
              t_make.wall, t_base.wall, t_prep.wall, t_render.wall, mpix / t_render.wall,
              100.0 * static_cast<double>(img.exact_pixels) / (static_cast<double>(size) * size));
  std::printf(" %7.2f", t_prep.cpu / std::max(t_render.cpu, 1e-9));
  const bool published = spline.degree() >= bench::kPublishedMinDegree && spline.degree() <= bench::kPublishedMaxDegree;
  if (published) {
    bench::PublishedRegion r;
    r.point = point;
    r.max_depth = o.max_depth;
    r.width = r.height = size;
    r.view = problem->view();
    std::vector<uint8_t> labels;
    const Best native = best_of(reps, [&] { labels = bench::published_region(spline, r); });
    const Best lanes = best_of(reps, [&] { labels = bench::published_region_lanes(spline, r, false); });
    const Best lockstep = best_of(reps, [&] { labels = bench::published_region_lanes(spline, r, true); });
    const double best = std::min({native.wall, lanes.wall, lockstep.wall});
    std::printf(" %9.4f %7.2fx", best, best / t_render.wall);
  } else {
    std::printf(" %9s %8s", "-", "-");
  }
  std::printf(" %4s %5.2f\n", problem->setup().fixed_none ? "yes" : "no", load_average());
  std::fflush(stdout);
}

void header(const char* title) {
  std::printf("\n%s\n", title);
  std::printf("  %-22s %5s %6s %9s %9s %9s %9s %8s %8s %7s %9s %8s %4s %5s\n", "scene", "deg", "spans", "setup s",
              "analysis", "prepare", "render s", "Mp/s", "exact", "prep/r", "pub s", "cmr/pub", "all0", "load");
}

int run(int argc, char** argv) {
  const int reps = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const std::string tables = argc > 2 ? argv[2] : "abc";
  utsname un{};
  uname(&un);
  std::printf("cmr region growth benchmark: %s, %u hardware threads, %s %s, load average %.2f\n", cpu_model().c_str(),
              std::thread::hardware_concurrency(), un.sysname, un.release, load_average());
  std::printf("CPU backend, fp64, certified labels (no depth map), D = %d, default view, best of %d\n"
              "(fewer passes where %.0f s are spent); seconds are wall-clock\n",
              kDefaultDepth, reps, kMeasureBudget);

  if (tables.find('a') != std::string::npos) {
    header("(a) image size: uniform cubic B-spline of fig8.json, P3");
    const BSpline fig8 = read_spline_file("examples/figures/fig8.json");
    for (const int size : {256, 512, 1024, 2048}) {
      const std::string name = "fig8 P3 " + std::to_string(size) + "^2";
      row(name.c_str(), fig8, 3, size, reps);
    }
  }
  if (tables.find('b') != std::string::npos) {
    header("(b) degree: spiral Bezier curves, the middle point moved, 512^2");
    for (int n = 3; n <= 15; ++n) {
      const std::string name = "spiral Bezier P" + std::to_string(n / 2);
      row(name.c_str(), spiral_bezier(n), n / 2, kDegreeSize, reps);
    }
  }
  if (tables.find('c') != std::string::npos) {
    header("(c) span count: uniform cubic B-splines, the middle point moved, 512^2");
    for (const int spans : {10, 100, 1000, 10000}) {
      const BSpline walk = random_walk(spans, 23);
      const BSpline spiral = spiral_spline(spans);
      row(("random walk " + std::to_string(spans)).c_str(), walk, walk.point_count() / 2, kDegreeSize, reps);
      row(("spiral " + std::to_string(spans)).c_str(), spiral, spiral.point_count() / 2, kDegreeSize, reps);
    }
  }
  std::printf("\n  setup s: RegionProblem::make (validation, analysis, preparation); analysis: region_base (the\n"
              "  spline before the move, every span classified); prepare: prepare_region given the analysis (the\n"
              "  moved spans' Bezier points and exact piece polynomials); render s: CpuRegionBackend::render;\n"
              "  exact: pixels the exact path decided; prep/r: prepare / render in CPU seconds of the process;\n"
              "  pub s: the published method's best form (native or vectorised, all cores; degrees %d..%d);\n"
              "  cmr/pub: its time / cmr's render time (> 1: cmr faster); all0: an untouched span fails, so every label\n"
              "  is 0 without per-pixel work; load: 1-minute load average after the row\n",
              bench::kPublishedMinDegree, bench::kPublishedMaxDegree);
  return 0;
}

}  // namespace

/// Run from the repository root (it reads examples/); any failure is one line.
int main(int argc, char** argv) {
  cmr::cli::keep_freed_memory();  // as cmr does (tools/keep_freed_memory.hpp)
  cmr::cli::read_environment();    // CMR_SIMD, CMR_BLOCK_REUSE, as cmr does
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_growth: %s\n", e.what());
    return 1;
  }
}
