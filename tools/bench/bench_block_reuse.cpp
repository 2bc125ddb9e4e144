// bench_block_reuse: the region CPU render's label maps with and without the
// reuse of failed block proofs (region/box_reuse.hpp, CMR_BLOCK_REUSE),
// on ONE thread, timed in CPU seconds of that thread (steady on a shared,
// loaded machine, where bench_region's all-core figures scatter), off and on
// interleaved, best of `reps` each. Cells as bench_region's: the cubic Bezier
// (fig2 P1), the uniform cubic (fig8 P3) and the degree-9 Bezier (bezier9
// P4); the whole region (default view), 10x wider, and a 4e-4 zoom centred on
// the first boundary point bench_region finds; D = 10 and 16; 512^2 and
// 1024^2. Also checks that both label maps are equal (exit 1 otherwise), and
// prints per frame how many nodes, segments and level-0 checks the blocks
// and the pixels took from a failed parent (BlockReuseCounts).
//
// Run from the repository root: build/tools/bench/bench_block_reuse [reps] [filter]
// (filter: a substring of "scene view D size", e.g. "zoom 16 512").
#include <time.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <utility>

#include "region/box_reuse.hpp"
#include "region/region.hpp"
#include "region/region_setup.hpp"
#include "spline/spline_json.hpp"

using namespace cmr;
using namespace cmr::backend;

namespace {

constexpr int kScanSize = 1024, kScanDepth = 12;  // bench_region's default view scan
constexpr double kWideFactor = 10, kZoomWidth = 4e-4;

RegionProblem prepare(const BSpline& spline, int point, int depth, int size, std::optional<View> view) {
  RegionRequest o;
  o.point = point;
  o.max_depth = depth;
  o.width = o.height = size;
  o.view = view;
  o.depth = false;
  return RegionProblem::make(spline, o);
}

double thread_cpu() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

View centred(Vec2 c, double hw, double hh) { return View{c.x - hw, c.y - hh, c.x + hw, c.y + hh}; }

// bench_region's boundary point: the first label change along a row of the
// default view (rows from the middle out), bisected 60 times on certified labels.
std::optional<Vec2> boundary_point(const RegionProblem& p) {
  const RegionSetup& s = p.setup();
  const RegionImage img = region_cpu(s, 1);
  const View v = p.view();
  for (int step = 0; step < kScanSize; ++step) {
    const int j = kScanSize / 2 + (step % 2 ? -(step + 1) / 2 : step / 2);
    for (int i = 1; i < kScanSize; ++i) {
      const std::size_t at = static_cast<std::size_t>(j) * kScanSize + i;
      if (img.labels[at] == img.labels[at - 1]) continue;
      Vec2 a = pixel_center(v, kScanSize, kScanSize, i - 1, j), b = pixel_center(v, kScanSize, kScanSize, i, j);
      const std::uint8_t left = classify_position(s, a).label;
      for (int k = 0; k < 60; ++k) {
        const Vec2 m = 0.5 * (a + b);
        (classify_position(s, m).label == left ? a : b) = m;
      }
      return 0.5 * (a + b);
    }
  }
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  const int reps = argc > 1 ? std::atoi(argv[1]) : 10;
  const std::string filter = argc > 2 ? argv[2] : "";
  if (reps < 1) {
    std::fprintf(stderr, "bench_block_reuse: reps must be a positive integer, got '%s'\n", argv[1]);
    return 2;
  }
  struct Scene {
    const char* name;
    const char* file;
    int point;
  };
  const Scene scenes[] = {{"cubic Bezier, P1", "examples/figures/fig2.json", 1},
                          {"uniform cubic, P3", "examples/figures/fig8.json", 3},
                          {"degree-9 Bezier, P4", "examples/bezier9.json", 4}};
  std::printf("region CPU render, labels only, one thread, CPU ms of that thread, best of %d, reuse off/on "
              "interleaved\n",
              reps);
  std::printf("| cell (scene, view, D, size) | reuse off, ms | reuse on, ms | off / on | taken by blocks | taken by "
              "pixels |\n|---|---:|---:|---:|---:|---:|\n");
  bool differ = false;
  for (const Scene& sc : scenes) {
    std::optional<BSpline> read;
    try {
      read.emplace(read_spline_file(sc.file));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_block_reuse: %s (run from the repository root)\n", e.what());
      return 2;
    }
    const BSpline& spline = *read;
    const RegionProblem base = prepare(spline, sc.point, kScanDepth, kScanSize, std::nullopt);
    const View v = base.view();
    const Vec2 centre{0.5 * (v.x0 + v.x1), 0.5 * (v.y0 + v.y1)};
    const View wide = centred(centre, kWideFactor * 0.5 * (v.x1 - v.x0), kWideFactor * 0.5 * (v.y1 - v.y0));
    const auto edge = boundary_point(base);
    if (!edge) {
      std::fprintf(stderr, "bench_block_reuse: no region boundary in the default view of %s\n", sc.name);
      return 1;
    }
    const View zoom = centred(*edge, 0.5 * kZoomWidth, 0.5 * kZoomWidth);
    for (const int depth : {10, 16})
      for (const int size : {512, 1024})
        for (const auto& [view_name, view] : {std::pair<const char*, std::optional<View>>{"whole region", std::nullopt},
                                              {"10x wider", wide},
                                              {"4e-4 zoom", zoom}}) {
          const std::string cell = std::string(sc.name) + " " + view_name + " " + std::to_string(depth) + " " +
                                   std::to_string(size);
          if (cell.find(filter) == std::string::npos) continue;
          const RegionProblem p = prepare(spline, sc.point, depth, size, view);
          double best[2] = {1e300, 1e300};
          RegionImage img[2];
          const BlockReuseCounts c0 = block_reuse_counts();
          for (int r = 0; r < reps; ++r)
            for (int on = 0; on < 2; ++on) {
              set_block_reuse(on);
              const double t0 = thread_cpu();
              img[on] = region_cpu(p.setup(), 1);
              best[on] = std::min(best[on], thread_cpu() - t0);
            }
          set_block_reuse(-1);
          const BlockReuseCounts c1 = block_reuse_counts();
          const auto per_frame = [&](std::uint64_t a, std::uint64_t b) { return static_cast<double>(b - a) / reps; };
          const double box = per_frame(c0.box_nodes + c0.box_segments + c0.box_level0,
                                       c1.box_nodes + c1.box_segments + c1.box_level0),
                       pix = per_frame(c0.pixel_nodes + c0.pixel_segments, c1.pixel_nodes + c1.pixel_segments);
          const bool same = img[0].labels == img[1].labels;
          differ = differ || !same;
          std::printf("| %s | %.2f | %.2f | %.2f | %.0f | %.0f |%s\n", cell.c_str(), 1e3 * best[0], 1e3 * best[1],
                      best[0] / best[1], box, pix, same ? "" : " LABELS DIFFER");
          std::fflush(stdout);
        }
  }
  return differ ? 1 : 0;
}
