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
//   - the baselines (tools/bench/published_method.hpp: the authors'
//     per-pixel method, fixed-degree straight-line code, plain double, all
//     cores; natively per pixel, vectorised across 4 pixels, and as a fp64
//     shader on the Vulkan device, fragment or compute, the faster) against cmr's
//     CPU and Vulkan backends, measured interleaved in the same run, for a
//     cubic Bezier (fig2.json P1), the uniform cubic (fig8.json P3) and the
//     degree-9 Bezier, in three views (the whole region, 10x wider, and a
//     4e-4-wide zoom centred on a point of a region boundary found by
//     bisection), at D = 10 and D = 16, 512^2 and 1024^2, ratios against the
//     faster baseline of each cell, with the number of pixels whose labels
//     differ and the load average.
// Usage: bench_region [repetitions=5] [cells [cmr|cmr-idle|vk|vk-whole|vk-culled|vk-cascade|all [SIZE,...]]]
//   (run from the repository root)
//   cells: only the comparison cells whose "scene view D size" text contains
//   this string (e.g. "zoom 16 512"), and no default-view section.
//   cmr: in those cells, only cmr's CPU backend (no baselines, no Vulkan),
//   exactly `repetitions` frames, 0.2 ms apart (settle() below): best
//   wall-clock and CPU seconds per frame,
//   for profiling and for comparing builds back to back (under callgrind,
//   instructions per frame: the difference of two repetition counts);
//   cmr-idle: the same, each frame after 5 ms with nothing to do; vk:
//   the same for its Vulkan backend (its DeviceShare as the device's type
//   picks it); vk-whole, vk-culled: with that share; vk-cascade: the whole
//   share as an fp32-then-fp64 cascade; all: every column, as
//   without.
//   SIZE,...: the comparison's image sides instead of 512 and 1024 (e.g.
//   2048, for a GPU's throughput).
#include <sys/utsname.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "spline/limits.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"
#include "tools/bench/published_method.hpp"
#include "tools/bench/published_method_vk.hpp"
#include "region/region.hpp"
#include "vk/backend_choice.hpp"
#include "vk/region_vk.hpp"
#include "tools/keep_freed_memory.hpp"

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
/// argv[3] == "vk-whole" / "vk-culled": the Vulkan backend with that
/// DeviceShare (vk: as the device's type picks it).
vk::DeviceShare g_share = vk::DeviceShare::automatic;
bool g_cascade = false;  ///< vk-cascade: VulkanRegionOptions::cascade
/// The Vulkan backend when made with an explicit share (vk-whole, vk-culled).
const vk::VulkanRegionBackend* g_vk_backend = nullptr;

/// Renders on the Vulkan device (lavapipe here) or on every CPU core; one
/// backend of each kind for the whole run, as `cmr region` keeps one. The
/// Vulkan one is never destroyed: a GPU driver may be gone by the time static
/// destructors run (vk/context.hpp).
RegionResult render(const RegionProblem& s, bool vulkan) {
  static CpuRegionBackend cpu;
  static auto& device = *new std::shared_ptr<RegionBackend>([] {
    if (g_share == vk::DeviceShare::automatic) return vk::make_region_backend({.kind = vk::BackendKind::vulkan});
    vk::VulkanRegionOptions o;
    o.share = g_share;
    o.cascade = g_cascade;
    auto b = vk::VulkanRegionBackend::create(o);
    if (!b) throw std::runtime_error(b.error().message);
    auto made = std::make_shared<vk::VulkanRegionBackend>(b.take());
    g_vk_backend = made.get();
    return std::shared_ptr<RegionBackend>(made);
  }());
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
constexpr int kCompareSize = 512;       ///< the smaller image side in the baseline comparison (the other: kSize)
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

/// Seconds of CPU time this process (every thread, lavapipe's included) has used.
/// The kernel adds a thread's time to the process's clock when the thread
/// stops running (or at a timer tick), so a worker that finished its last
/// job a few microseconds ago may not be counted yet: a measured function's
/// end is read after settle().
double cpu_now() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Waits until the threads that ran a measured function have gone to sleep
/// (a pool's worker returns to its wait within microseconds of its last
/// job), so that cpu_now() counts their time.
void settle() { std::this_thread::sleep_for(std::chrono::microseconds(200)); }

/// Best wall-clock seconds (wall) and best CPU seconds of the process (cpu)
/// of each of fs, measured interleaved: round r runs every function once, in
/// turn, so that load on the shared machine falls on all of them alike;
/// stops after `reps` rounds or kMeasureBudget seconds per function (at
/// least one round). On a loaded machine the CPU seconds are the steadier
/// figure (time spent waiting for a core is not counted).
template <std::size_t K>
struct Timings {
  std::array<double, K> wall, cpu;
};
template <std::size_t K>
Timings<K> best_interleaved(int reps, const std::array<std::function<void()>, K>& fs) {
  Timings<K> best;
  best.wall.fill(1e300);
  best.cpu.fill(1e300);
  double spent = 0;
  for (int r = 0; r < reps && spent < kMeasureBudget * K; ++r)
    for (std::size_t k = 0; k < K; ++k) {
      const double c0 = cpu_now(), t0 = now();
      fs[k]();
      const double t = now() - t0;
      settle();
      best.wall[k] = std::min(best.wall[k], t);
      best.cpu[k] = std::min(best.cpu[k], cpu_now() - c0);
      spent += t;
    }
  return best;
}

double load_average() {
  double l = 0;
  std::ifstream("/proc/loadavg") >> l;
  return l;
}

/// Cells whose "scene view D size" text contains this (argv[2]); empty: every cell.
std::string g_only;
/// argv[3] == "cmr": only cmr's CPU backend is timed in those cells; "vk":
/// only its Vulkan backend (for profiling one backend).
bool g_cmr_only = false;
bool g_vk_only = false;
/// argv[3] == "cmr-idle": as "cmr", each frame after kIdleGap with nothing
/// to do, as a frame of a drag comes in the editor (the pool's worker then
/// has to be woken: docs/performance.md, "An idle core joins late").
bool g_idle = false;
constexpr auto kIdleGap = std::chrono::milliseconds(5);
/// The comparison's image sides (argv[4]; default kCompareSize, kSize).
std::vector<int> g_sizes;

/// One line of the comparison: the baselines (published method native, its
/// vectorised form) vs cmr CPU and cmr Vulkan; ratios against the best baseline.
void compare(const Scene& sc, const char* view_name, std::optional<View> view, int depth, int size, int reps) {
  if (!g_only.empty() && (std::string(sc.name) + " " + view_name + " " + std::to_string(depth) + " " +
                          std::to_string(size)).find(g_only) == std::string::npos)
    return;
  const RegionProblem setup = prepare(*sc.spline, sc.point, depth, size, view);
  if (g_cmr_only) {
    // Exactly `reps` frames (no time budget): instruction counts under
    // callgrind scale with reps.
    Timings<1> tc;
    tc.wall.fill(1e300);
    tc.cpu.fill(1e300);
    for (int k = 0; k < reps; ++k) {
      if (g_idle) std::this_thread::sleep_for(kIdleGap);
      const double c0 = cpu_now(), t0 = now();
      (void)render(setup, g_vk_only);
      tc.wall[0] = std::min(tc.wall[0], now() - t0);
      settle();
      tc.cpu[0] = std::min(tc.cpu[0], cpu_now() - c0);
    }
    std::printf("  %-20s %-12s %2d %4d  cmr %s %8.3f ms wall %8.3f ms CPU %8.2f Mp/s", sc.name, view_name, depth, size,
                g_vk_only ? "Vulkan" : g_idle ? "CPU, each frame after 5 ms idle," : "CPU",
                1e3 * tc.wall[0], 1e3 * tc.cpu[0], static_cast<double>(size) * size / 1e6 / tc.wall[0]);
    if (g_vk_only && g_vk_backend && g_vk_backend->share() == vk::DeviceShare::whole) {
      // What the device's tile pass proved and what it left to the host.
      const vk::VulkanRegionBackend::WholeFrame& f = g_vk_backend->last_whole_frame();
      std::printf("  tiles queued %zu/%zu, flagged %zu", f.tiles_queued, f.tiles, f.flagged);
      if (g_cascade) std::printf(" (fp32 flagged %zu)", f.second);
      // The device's own time per pass (timestamps), where it has them.
      if (!f.pass_seconds.empty()) {
        std::printf("; device ms:");
        const char* names[] = {" tiles", " pixels", " fp64"};
        for (std::size_t k = 0; k < f.pass_seconds.size() && k < 3; ++k)
          std::printf("%s %.3f", names[k], 1e3 * f.pass_seconds[k]);
      }
    }
    std::printf("\n");
    std::fflush(stdout);
    return;
  }
  bench::PublishedRegion r;
  r.point = sc.point;
  r.max_depth = depth;
  r.width = r.height = size;
  r.view = view_of(setup);
  std::vector<uint8_t> ours, lanes, lockstep, shaded, computed;
  RegionResult img;
  using bench::ShaderStage;
  // Compile this degree/depth/size's pipelines untimed.
  (void)bench::published_region_vulkan(*sc.spline, r, ShaderStage::fragment);
  (void)bench::published_region_vulkan(*sc.spline, r, ShaderStage::compute);
  const Timings<7> timings = best_interleaved<7>(
      reps, {[&] { ours = bench::published_region(*sc.spline, r); },
             [&] { lanes = bench::published_region_lanes(*sc.spline, r, false); },
             [&] { lockstep = bench::published_region_lanes(*sc.spline, r, true); },
             [&] { shaded = bench::published_region_vulkan(*sc.spline, r, ShaderStage::fragment); },
             [&] { computed = bench::published_region_vulkan(*sc.spline, r, ShaderStage::compute); },
             [&] { img = render(setup, false); }, [&] { (void)render(setup, true); }});
  const std::array<double, 7>& t = timings.wall;
  const std::array<double, 7>& c = timings.cpu;
  const double tp = t[0], ts = std::min(t[1], t[2]), tg = std::min(t[3], t[4]), tc = t[5], tv = t[6],
               tb = std::min({tp, ts, tg});
  const double cb = std::min({c[0], c[1], c[2], c[3], c[4]});
  long differ = 0, lanes_differ = 0;
  for (std::size_t k = 0; k < ours.size(); ++k) {
    differ += ours[k] != img.code_at(k);
    lanes_differ += (ours[k] != lanes[k]) + (ours[k] != lockstep[k]) + (ours[k] != shaded[k]) + (ours[k] != computed[k]);
  }
  const double mpix = static_cast<double>(ours.size()) / 1e6;
  std::printf(
      "  %-20s %-12s %2d %4d %8.2f %8.2f %8.2f %8.2f %8.2f %7.2fx %7.2fx %7.2fx %7.2fx %6ld %4ld %6.3f%% %5.2f\n",
      sc.name, view_name, depth, size, mpix / tp, mpix / ts, mpix / tg, mpix / tc, mpix / tv, tb / tc, tb / tv,
      cb / c[5], cb / c[6], differ, lanes_differ, 100.0 * static_cast<double>(img.exact_pixels) / ours.size(),
      load_average());
  std::fflush(stdout);
}

void print_comparison(const std::vector<Scene>& scenes, int reps) {
  std::printf("\nbaselines (the published method, plain double: native per pixel on all cores, vectorised\n"
              "across 4 pixels (%s), and as a fp64 shader on the Vulkan\n"
              "device, fragment or compute) vs cmr (certified), measured interleaved, best of %d:\n",
#ifdef CMR_BENCH_AVX2
              "AVX2: 4 doubles per instruction",
#else
              "the project's flags: SSE2, 2 doubles per instruction",
#endif
              reps);
  std::printf("  %-20s %-12s %2s %4s %8s %8s %8s %8s %8s %8s %8s %8s %8s %6s %4s %7s %5s\n", "scene", "view", "D",
              "size", "pub Mp/s", "vec Mp/s", "shd Mp/s", "CPU Mp/s", "Vk Mp/s", "CPU/best", "Vk/best", "CPU/b cs",
              "Vk/b cs", "differ", "vecd", "exact", "load");
  for (const Scene& sc : scenes) {
    const RegionProblem base = prepare(*sc.spline, sc.point, kDefaultDepth, kSize, std::nullopt);
    const View v = view_of(base);
    const Vec2 centre{0.5 * (v.x0 + v.x1), 0.5 * (v.y0 + v.y1)};
    const View wide = centred(centre, kWideFactor * 0.5 * (v.x1 - v.x0), kWideFactor * 0.5 * (v.y1 - v.y0));
    const Vec2 edge = boundary_point(base, render(base, false));
    const View zoom = centred(edge, 0.5 * kZoomWidth, 0.5 * kZoomWidth);
    for (const int depth : {10, 16}) {
      // Compile this depth's pipeline untimed: a small image across the boundary reaches the device.
      if (!g_cmr_only) (void)render(prepare(*sc.spline, sc.point, depth, kWarmupSize, zoom), true);
      for (const int size : g_sizes) {
        compare(sc, "whole region", std::nullopt, depth, size, reps);
        compare(sc, "10x wider", wide, depth, size, reps);
        compare(sc, "4e-4 zoom", zoom, depth, size, reps);
      }
    }
    std::printf("  (%s: zoom centred on the boundary point (%.12g, %.12g))\n", sc.name, edge.x, edge.y);
  }
  std::printf("  vec: the faster of the two vectorised forms (level 0 vectorised, lock step); shd: the faster of\n"
              "  the shader's two forms (shaders/published_fp64.glsl as one fragment or one compute invocation per\n"
              "  pixel, every pixel shaded, pipelines compiled untimed); best: the fastest\n"
              "  baseline of the cell (wall-clock); CPU/b cs, Vk/b cs: the same ratios in CPU seconds of the process\n"
              "  (every thread; the steadier figure on a loaded machine); differ: pixels whose published label is\n"
              "  not the certified one;\n"
              "  vecd: pixels where the vectorised or shader baseline differs from the native one (0: same arithmetic);\n"
              "  exact: pixels cmr's exact path decided; load: 1-minute load average after the cell\n");
}


int run(int argc, char** argv) {
  setenv("MESA_SHADER_CACHE_DISABLE", "true", 1);  // time to first image includes compilation
  const int reps = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  if (argc > 2) g_only = argv[2];
  const std::string mode = argc > 3 ? argv[3] : "all";
  if (mode == "vk-whole") g_share = vk::DeviceShare::whole;
  if (mode == "vk-culled") g_share = vk::DeviceShare::culled;
  if (mode == "vk-cascade") g_share = vk::DeviceShare::whole, g_cascade = true;
  g_vk_only = mode == "vk" || mode == "vk-whole" || mode == "vk-culled" || mode == "vk-cascade";
  g_idle = mode == "cmr-idle";
  g_cmr_only = mode == "cmr" || g_idle || g_vk_only;
  g_sizes = {kCompareSize, kSize};
  if (argc > 4) {
    g_sizes.clear();
    for (const char* at = argv[4]; *at != '\0';) {
      char* end = nullptr;
      const long side = std::strtol(at, &end, 10);
      if (end == at || side < 1 || side > 16384) throw std::runtime_error(std::string("bad image side in '") + argv[4] + "'");
      g_sizes.push_back(static_cast<int>(side));
      at = *end == ',' ? end + 1 : end;
      if (*end != ',' && *end != '\0') throw std::runtime_error(std::string("bad image side in '") + argv[4] + "'");
    }
  }
  utsname un{};
  uname(&un);
  std::printf("cmr region benchmark: %s, %u hardware threads, %s %s, load average %.2f\n", cpu_model().c_str(),
              std::thread::hardware_concurrency(), un.sysname, un.release, load_average());
  std::printf("1024x1024, D = 12, fp64, certified labels, default view, best of %d (fewer where %.0f s are spent)\n\n",
              reps, kMeasureBudget);

  const BSpline uniform = read_spline_file("examples/figures/fig8.json");
  const BSpline bezier9 = read_spline_file("examples/bezier9.json");
  if (g_only.empty()) {
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
  }
  const BSpline cubic = read_spline_file("examples/figures/fig2.json");
  print_comparison({{"cubic Bezier, P1", &cubic, 1}, {"uniform cubic, P3", &uniform, 3}, {"degree-9 Bezier, P4", &bezier9, 4}},
                   reps);
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
    std::fprintf(stderr, "bench_region: %s\n", e.what());
    return 1;
  }
}
