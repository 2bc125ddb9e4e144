// Region benchmark (issues: regions on Vulkan; certified and fast regions).
// Prints, for 1024x1024 label maps (no depth map), depth 12, fp64, certified labels, the region
// in view (default view):
//   - the uniform cubic B-spline of examples/figures/fig8.json, one control
//     point (P3), on the Vulkan device (lavapipe here) and on the CPU backend;
//   - the same spline with every control point overlapped (--point all), as
//     frames per second;
//   - the degree-9 Bezier curve of examples/bezier9.json, point P4;
//   - time to the first image in a fresh process state, shader compilation
//     included (the Mesa shader cache is disabled for this program);
//   - the method as first published, measured in the same run: per pixel,
//     rebuild the moved segments' Bezier points, form lambda from hodograph
//     products and run Algorithm 1 in plain double (no certification, no
//     culling), on all cores; and the ratio.
// Usage: bench_region [repetitions=5]   (run from the repository root)
#include <sys/utsname.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "bezierize/classify.hpp"
#include "bezierize/extract.hpp"
#include "bezierize/lambda.hpp"
#include "spline/spline_json.hpp"
#include "bezierize/region.hpp"
#include "vk/region_vk.hpp"

using namespace cmr;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

// Best of `reps` wall-clock seconds of f().
template <class F>
double best_of(int reps, F f) {
  double best = 1e300;
  for (int r = 0; r < reps; ++r) {
    const double t0 = now();
    f();
    best = std::min(best, now() - t0);
  }
  return best;
}

// The method as first published (CAD&A 2024 §3), on the CPU: every pixel
// rebuilds the touched segments and decides them in plain double.
std::vector<uint8_t> published_method(const BSpline& spline, const RegionRequest& o, int threads) {
  const View v = *o.view;
  const auto infl = influence(spline, {o.point});
  const auto base = bezier_segments(spline);
  std::vector<uint8_t> labels(static_cast<std::size_t>(o.width) * o.height);
  std::atomic<int> next{0};
  auto work = [&] {
    std::vector<Vec2> P(spline.degree() + 1);
    for (int j = next++; j < o.height; j = next++)
      for (int i = 0; i < o.width; ++i) {
        const Vec2 p = pixel_center(v, o.width, o.height, i, j);
        const Vec2 d = p - spline.points()[o.point];
        bool inc = false, dec = false, none = false;
        for (const SegmentInfluence& si : infl) {
          for (int k = 0; k <= spline.degree(); ++k) P[k] = base[si.segment].points[k] + si.w[k] * d;
          const auto m = algorithm1(lambda_bernstein<double>(P), o.max_depth);
          switch (m->curvature) {
            case Curvature::increasing: inc = true; break;
            case Curvature::decreasing: dec = true; break;
            default: none = true; break;
          }
        }
        labels[static_cast<std::size_t>(j) * o.width + i] = none || (inc && dec) ? 0 : (inc ? 1 : 2);
      }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  return labels;
}

}  // namespace

int main(int argc, char** argv) {
  setenv("MESA_SHADER_CACHE_DISABLE", "true", 1);  // time to first image includes compilation
  const int reps = argc > 1 ? std::atoi(argv[1]) : 5;
  const int size = 1024;
  const double mpix = size * size / 1e6;
  utsname un{};
  uname(&un);
  std::printf("cmr region benchmark: %s, %u hardware threads, %s %s\n", cpu_model().c_str(),
              std::thread::hardware_concurrency(), un.sysname, un.release);
  std::printf("1024x1024, D = 12, fp64, certified labels, default view, best of %d\n\n", reps);

  const BSpline uniform = read_spline_file("examples/figures/fig8.json");
  const BSpline bezier9 = read_spline_file("examples/bezier9.json");
  RegionRequest o;
  o.width = o.height = size;
  o.point = 3;
  o.depth = false;  // label maps, as `cmr region` without --depth-map
  const RegionProblem one = RegionProblem::make(uniform, o);
  CpuRegionBackend cpu;

  const double t_first0 = now();
  auto created = cmr::vk::VulkanRegionBackend::create();
  if (!created) {
    std::fprintf(stderr, "bench_region: %s\n", created.error().message.c_str());
    return 3;
  }
  cmr::vk::VulkanRegionBackend vk = created.take();
  const RegionResult first = vk.render(one);
  const double t_first = now() - t_first0;
  const double compile = first.setup_seconds;

  std::printf("%-58s %12s %12s\n", "scene", "Vulkan", "CPU backend");
  auto row = [&](const char* name, const RegionProblem& s) {
    const double tv = best_of(reps, [&] { (void)vk.render(s); });
    const double tc = best_of(reps, [&] { (void)cpu.render(s); });
    std::printf("%-58s %7.1f Mp/s %7.1f Mp/s\n", name, mpix / tv, mpix / tc);
    return std::pair{tv, tc};
  };
  row("uniform cubic B-spline, 6 points, P3 (fig8.json)", one);

  std::vector<RegionProblem> all;
  for (int k = 0; k < uniform.point_count(); ++k) {
    RegionRequest ok = o;
    ok.point = k;
    all.push_back(RegionProblem::make(uniform, ok));
  }
  const double fv = best_of(reps, [&] { for (auto& s : all) (void)vk.render(s); });
  const double fc = best_of(reps, [&] { for (auto& s : all) (void)cpu.render(s); });
  std::printf("%-58s %6.1f fps    %6.1f fps\n", "same spline, every point overlapped (--point all)", 1 / fv, 1 / fc);

  RegionRequest o9 = o;
  o9.point = 4;
  const RegionProblem nine = RegionProblem::make(bezier9, o9);
  row("degree-9 Bezier, P4 (bezier9.json)", nine);

  std::printf("\ntime to first image (Vulkan context, shader compile %.3f s, render): %.3f s\n", compile, t_first);
  std::printf("share of pixels the exact path decided (Vulkan, fig8 P3): %.4f%%\n",
              100.0 * static_cast<double>(first.exact_pixels) / (size * size));

  // Before/after, one run: the published per-pixel method against cmr.
  const int threads = static_cast<int>(std::thread::hardware_concurrency());
  std::printf("\nbefore/after (same machine, same run):\n");
  for (const auto& [name, spline, setup] :
       {std::tuple{"uniform cubic, P3", &uniform, &one}, std::tuple{"degree-9 Bezier, P4", &bezier9, &nine}}) {
    const double tb = best_of(std::max(1, reps / 2), [&] { (void)published_method(*spline, setup->request(), threads); });
    const double ta = best_of(reps, [&] { (void)vk.render(*setup); });
    std::printf("  %-22s published method (CPU, %d threads): %7.2f Mp/s   cmr Vulkan: %7.1f Mp/s   ratio %.0fx\n", name,
                threads, mpix / tb, mpix / ta, tb / ta);
  }
  return 0;
}
