// Region benchmark (issues: regions on Vulkan; certified and fast regions; one
// region engine). Prints, for 1024x1024 label maps (no depth map), fp64,
// certified labels:
//   - at D = 12 in the default view (the region in it): the uniform cubic
//     B-spline of examples/figures/fig8.json, one control point (P3), on the
//     Vulkan device (lavapipe here) and on the CPU backend; the same spline
//     with every control point overlapped (--point all), as frames per second;
//     the degree-9 Bezier curve of examples/bezier9.json, point P4; time to the
//     first image in a fresh process state, shader compilation included (the
//     Mesa shader cache is disabled for this program);
//   - the published method (tools/bench/published_method.hpp: the authors'
//     per-pixel method, fixed-degree straight-line code, plain double, all
//     cores) against cmr's CPU and Vulkan backends, measured in the same run,
//     in three views (the whole region, 10x wider, and a 4e-4-wide zoom
//     centred on a point of a region boundary found by bisection), at D = 10
//     and D = 16, with the number of pixels whose labels differ.
// Usage: bench_region [repetitions=5]   (run from the repository root)
#include <sys/utsname.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <thread>

#include "spline/limits.hpp"
#include "spline/spline_json.hpp"
#include "tools/bench/published_method.hpp"
#include "bezierize/region.hpp"
#include "vk/backend_choice.hpp"

using namespace cmr;

namespace {

// ---- The only section that calls cmr's region API ------------------------

/// One prepared region image of `spline` with `point` moved.
RegionProblem prepare(const BSpline& spline, int point, int depth, int size, std::optional<View> view) {
  RegionRequest o;
  o.point = point;
  o.max_depth = depth;
  o.width = o.height = size;
  o.view = view;
  o.depth = false;  // label maps, as `cmr region` without --depth-map
  return RegionProblem::make(spline, o);
}

View view_of(const RegionProblem& s) { return s.view(); }

double g_shader_setup_seconds = 0;

/// Renders on the Vulkan device (lavapipe here) or on every CPU core; one
/// backend of each kind for the whole run, as `cmr region` keeps one.
RegionResult render(const RegionProblem& s, bool vulkan) {
  static CpuRegionBackend cpu;
  static std::shared_ptr<RegionBackend> device = vk::make_region_backend({vk::BackendKind::vulkan, {}, {}});
  RegionResult r = (vulkan ? *device : static_cast<RegionBackend&>(cpu)).render(s);
  if (vulkan) g_shader_setup_seconds += r.setup_seconds;
  return r;
}

/// Seconds spent compiling shaders so far.
double shader_setup_seconds() { return g_shader_setup_seconds; }

/// The certified label of position p, as its label-map byte.
uint8_t certified_label(const RegionProblem& s, Vec2 p) { return code(s.classify(p).label); }

// ---- Measurement ----------------------------------------------------------

constexpr int kSize = 1024;
constexpr double kMpix = kSize * kSize / 1e6;
constexpr int kCompareSize = 512;       ///< image side in the published-method comparison
constexpr double kWideFactor = 10;      ///< the wide view: this times the default view's extent
constexpr double kZoomWidth = 4e-4;     ///< the zoom's world width, centred on a boundary point
constexpr int kBisectionSteps = 60;     ///< halvings of the boundary bracket (2^-60 of a pixel)
constexpr double kMeasureBudget = 2.0;  ///< seconds: no further passes of one measurement after this
constexpr int kWarmupSize = 16;         ///< image side of the untimed render that compiles a pipeline

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

// Best of `reps` wall-clock seconds of f(), or of fewer passes once they
// have taken kMeasureBudget seconds together (at least one pass).
template <class F>
double best_of(int reps, F f) {
  double best = 1e300, spent = 0;
  for (int r = 0; r < reps && spent < kMeasureBudget; ++r) {
    const double t0 = now();
    f();
    const double t = now() - t0;
    best = std::min(best, t);
    spent += t;
  }
  return best;
}

View centred(Vec2 centre, double half_w, double half_h) {
  return View{centre.x - half_w, centre.y - half_h, centre.x + half_w, centre.y + half_h};
}

/// A point on a region boundary: the first label change between neighbouring
/// pixels of a row of the default view (rows from the middle out), refined by
/// bisection on certified labels.
Vec2 boundary_point(const RegionProblem& s, const RegionResult& img) {
  const View v = view_of(s);
  for (int step = 0; step < kSize; ++step) {
    const int j = kSize / 2 + (step % 2 ? -(step + 1) / 2 : step / 2);
    for (int i = 1; i < kSize; ++i) {
      const uint8_t left = img.code_at(static_cast<std::size_t>(j) * kSize + i - 1);
      if (img.code_at(static_cast<std::size_t>(j) * kSize + i) == left) continue;
      Vec2 a = pixel_center(v, kSize, kSize, i - 1, j), b = pixel_center(v, kSize, kSize, i, j);
      for (int k = 0; k < kBisectionSteps; ++k) {
        const Vec2 m = 0.5 * (a + b);
        (certified_label(s, m) == left ? a : b) = m;
      }
      return 0.5 * (a + b);
    }
  }
  std::fprintf(stderr, "bench_region: no region boundary in the default view\n");
  std::exit(1);
}

struct Scene {
  const char* name;
  const BSpline* spline;
  int point;
};

/// One line of the comparison: published method vs cmr CPU vs cmr Vulkan.
void compare(const Scene& sc, const char* view_name, std::optional<View> view, int depth, int reps) {
  const RegionProblem setup = prepare(*sc.spline, sc.point, depth, kCompareSize, view);
  bench::PublishedRegion r;
  r.point = sc.point;
  r.max_depth = depth;
  r.width = r.height = kCompareSize;
  r.view = view_of(setup);
  std::vector<uint8_t> ours;
  const double tp = best_of(reps, [&] { ours = bench::published_region(*sc.spline, r); });
  RegionResult img;
  const double tc = best_of(reps, [&] { img = render(setup, false); });
  const double tv = best_of(reps, [&] { (void)render(setup, true); });
  long differ = 0;
  for (std::size_t k = 0; k < ours.size(); ++k) differ += ours[k] != img.code_at(k);
  const double mpix = static_cast<double>(ours.size()) / 1e6;
  std::printf("  %-20s %-13s %2d %9.2f %9.2f %9.2f %8.2fx %7.2fx %8ld %7.3f%%\n", sc.name, view_name, depth, mpix / tp,
              mpix / tc, mpix / tv, tp / tc, tp / tv, differ, 100.0 * static_cast<double>(img.exact_pixels) / ours.size());
}

void print_comparison(const std::vector<Scene>& scenes, int reps) {
  std::printf("\npublished method (all cores, plain double) vs cmr (certified), %dx%d, same run, best of %d:\n",
              kCompareSize, kCompareSize, reps);
  std::printf("  %-20s %-13s %2s %9s %9s %9s %9s %8s %8s %8s\n", "scene", "view", "D", "pub Mp/s", "CPU Mp/s",
              "Vk Mp/s", "CPU/pub", "Vk/pub", "differ", "exact");
  for (const Scene& sc : scenes) {
    const RegionProblem base = prepare(*sc.spline, sc.point, kDefaultDepth, kSize, std::nullopt);
    const View v = view_of(base);
    const Vec2 centre{0.5 * (v.x0 + v.x1), 0.5 * (v.y0 + v.y1)};
    const View wide = centred(centre, kWideFactor * 0.5 * (v.x1 - v.x0), kWideFactor * 0.5 * (v.y1 - v.y0));
    const Vec2 edge = boundary_point(base, render(base, false));
    const View zoom = centred(edge, 0.5 * kZoomWidth, 0.5 * kZoomWidth);
    for (const int depth : {10, 16}) {
      // Compile this depth's pipeline untimed: a small image across the boundary reaches the device.
      (void)render(prepare(*sc.spline, sc.point, depth, kWarmupSize, zoom), true);
      compare(sc, "whole region", std::nullopt, depth, reps);
      compare(sc, "10x wider", wide, depth, reps);
      compare(sc, "4e-4 zoom", zoom, depth, reps);
    }
    std::printf("  (%s: zoom centred on the boundary point (%.12g, %.12g))\n", sc.name, edge.x, edge.y);
  }
  std::printf("  differ: pixels whose published label is not the certified one; exact: pixels cmr's exact path decided\n");
}

}  // namespace

int main(int argc, char** argv) {
  setenv("MESA_SHADER_CACHE_DISABLE", "true", 1);  // time to first image includes compilation
  const int reps = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  utsname un{};
  uname(&un);
  std::printf("cmr region benchmark: %s, %u hardware threads, %s %s\n", cpu_model().c_str(),
              std::thread::hardware_concurrency(), un.sysname, un.release);
  std::printf("1024x1024, D = 12, fp64, certified labels, default view, best of %d (fewer where %.0f s are spent)\n\n",
              reps, kMeasureBudget);

  const BSpline uniform = read_spline_file("examples/figures/fig8.json");
  const BSpline bezier9 = read_spline_file("examples/bezier9.json");
  const RegionProblem one = prepare(uniform, 3, kDefaultDepth, kSize, std::nullopt);

  const double t_first0 = now();
  const RegionResult first = render(one, true);
  const double t_first = now() - t_first0;
  const double compile = shader_setup_seconds();

  std::printf("%-58s %12s %12s\n", "scene", "Vulkan", "CPU backend");
  auto row = [&](const char* name, const RegionProblem& s) {
    const double tv = best_of(reps, [&] { (void)render(s, true); });
    const double tc = best_of(reps, [&] { (void)render(s, false); });
    std::printf("%-58s %7.1f Mp/s %7.1f Mp/s\n", name, kMpix / tv, kMpix / tc);
  };
  row("uniform cubic B-spline, 6 points, P3 (fig8.json)", one);

  std::vector<RegionProblem> all;
  for (int k = 0; k < uniform.point_count(); ++k) all.push_back(prepare(uniform, k, kDefaultDepth, kSize, std::nullopt));
  const double fv = best_of(reps, [&] { for (auto& s : all) (void)render(s, true); });
  const double fc = best_of(reps, [&] { for (auto& s : all) (void)render(s, false); });
  std::printf("%-58s %6.1f fps    %6.1f fps\n", "same spline, every point overlapped (--point all)", 1 / fv, 1 / fc);

  row("degree-9 Bezier, P4 (bezier9.json)", prepare(bezier9, 4, kDefaultDepth, kSize, std::nullopt));

  std::printf("\ntime to first image (Vulkan context, shader compile %.3f s, render): %.3f s\n", compile, t_first);
  std::printf("share of pixels the exact path decided (Vulkan, fig8 P3): %.4f%%\n",
              100.0 * static_cast<double>(first.exact_pixels) / (kSize * kSize));

  print_comparison({{"uniform cubic, P3", &uniform, 3}, {"degree-9 Bezier, P4", &bezier9, 4}}, reps);
  return 0;
}
