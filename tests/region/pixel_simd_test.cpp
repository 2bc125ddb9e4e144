// SIMD across pixels in the CPU region render (region/pixel_simd.hpp):
//  - the kernel: every level's root values and bound are bit-identical to
//    the scalar code's, for the kernel sizes of the scenes below and others;
//  - CMR_SIMD's parsing and its one stderr line for a bad value;
//  - the render: label maps and depth maps at each forced level (scalar,
//    sse2, avx2 where the CPU has it) are equal pixel for pixel, and equal
//    to the exact path's, on a cubic Bezier (fig2 P1), the uniform cubic
//    fig8 P3, a quartic Bezier (P1, n1 = 10), the degree-9 Bezier (P4) and a
//    rational cubic (examples/rational/nurbs_cubic.json P3, n1 = 13), in the
//    default view and seeded zooms onto a region boundary (20 or 12 pixels); the pixels that went through the batch path
//    are counted (each scene and level must have some), and a deliberately
//    wrong batch (lane 1's v[0] negated) must be caught by the comparison.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "numeric/halve_pairs.hpp"
#include "region/pixel_lanes.hpp"
#include "region/pixel_simd.hpp"
#include "region/region.hpp"
#include "region/region_setup.hpp"
#include "spline/spline_json.hpp"
#include "tests/region/boundary_point.hpp"

namespace cmr {
namespace {

using namespace cmr::backend;

const std::string kSource = CMR_SOURCE_DIR;

// The levels this CPU runs; the test helper treats a level it claims but
// cannot force as an error.
std::vector<SimdLevel> levels() {
  std::vector<SimdLevel> out;
  for (const SimdLevel l : {SimdLevel::scalar, SimdLevel::sse2, SimdLevel::avx2})
    if (simd_available(l)) out.push_back(l);
  return out;
}

// Sets a level for the scope and restores the process's level after it.
class ForcedLevel {
 public:
  explicit ForcedLevel(SimdLevel l) : saved_(simd_level()) { EXPECT_TRUE(set_simd_level(l)) << simd_name(l); }
  ~ForcedLevel() { set_simd_level(saved_); }

 private:
  SimdLevel saved_;
};

class Fault {
 public:
  Fault() { set_simd_fault_for_test(true); }
  ~Fault() { set_simd_fault_for_test(false); }
};

TEST(PixelSimd, LevelsParseAndFallBackWithOneLine) {
  // The process's level (the library reads no environment; ctest's
  // pixel_simd_bad_env checks cmr's one stderr line under CMR_SIMD=fast).
  EXPECT_TRUE(simd_available(simd_level()));
  EXPECT_EQ(parse_simd_level("scalar"), SimdLevel::scalar);
  EXPECT_EQ(parse_simd_level("sse2"), SimdLevel::sse2);
  EXPECT_EQ(parse_simd_level("avx2"), SimdLevel::avx2);
  EXPECT_EQ(parse_simd_level("AVX2"), std::nullopt);
  EXPECT_EQ(parse_simd_level("avx512"), std::nullopt);
  EXPECT_EQ(parse_simd_level(""), std::nullopt);
  std::string warning = "stale";
  EXPECT_EQ(simd_level_for(nullptr, warning), best_simd_level());
  EXPECT_EQ(warning, "");
  EXPECT_EQ(simd_level_for("", warning), best_simd_level());
  EXPECT_EQ(warning, "");
  EXPECT_EQ(simd_level_for("scalar", warning), SimdLevel::scalar);
  EXPECT_EQ(warning, "");
  EXPECT_EQ(simd_level_for("fast", warning), best_simd_level());
  EXPECT_EQ(warning, std::string("cmr: CMR_SIMD=fast is not scalar, sse2 or avx2; using ") +
                         simd_name(best_simd_level()));
  EXPECT_EQ(warning.find('\n'), std::string::npos);
  for (const SimdLevel l : {SimdLevel::sse2, SimdLevel::avx2}) {
    const SimdLevel got = simd_level_for(simd_name(l), warning);
    if (simd_available(l)) {
      EXPECT_EQ(got, l);
      EXPECT_EQ(warning, "");
    } else {
      EXPECT_EQ(got, best_simd_level());
      EXPECT_EQ(warning, std::string("cmr: CMR_SIMD=") + simd_name(l) + ": this CPU or build lacks it; using " +
                             simd_name(best_simd_level()));
    }
  }
  EXPECT_EQ(simd_lanes(SimdLevel::scalar), 1);
  EXPECT_EQ(simd_lanes(SimdLevel::sse2), 2);
  EXPECT_EQ(simd_lanes(SimdLevel::avx2), 4);
#if defined(__x86_64__)
  EXPECT_TRUE(simd_available(SimdLevel::sse2));  // the x86-64 baseline
#endif
}

// The kernel's root values and bounds at every level against the scalar
// code's, bit for bit, on random coefficients and displacements of many
// magnitudes (signs, zeros and a -0 among them).
TEST(PixelSimd, RootValuesAreBitIdenticalAtEveryLevel) {
  std::mt19937_64 rng(2323);
  std::uniform_real_distribution<double> unit(-1, 1), expo(-30, 30);
  const auto number = [&] {
    const double r = unit(rng);
    if (r > 0.95) return 0.0;
    if (r < -0.95) return -0.0;
    return unit(rng) * std::exp2(expo(rng));
  };
  const double units = kPolyErrorUnits * 0.5 * Bounded::kRound, tiny = 16 * Bounded::kTiny;
  int compared = 0;
  for (const int n1 : {6, 10, 13, 14, 30, 37}) {
    for (int trial = 0; trial < 50; ++trial) {
      std::vector<double> t(static_cast<std::size_t>(10) * n1), mag(10, 0.0);
      for (int m = 0; m < 10; ++m)
        for (int c = 0; c < n1; ++c) {
          t[static_cast<std::size_t>(m) * n1 + c] = number();
          mag[m] = std::max(mag[m], std::fabs(t[static_cast<std::size_t>(m) * n1 + c]));
        }
      constexpr int kStride = 8;
      double dx[kStride], dy[kStride];
      for (int p = 0; p < kStride; ++p) {
        dx[p] = number();
        dy[p] = number();
      }
      std::vector<double> want(static_cast<std::size_t>(n1) * kStride), want_e(kStride);
      for (int p = 0; p < kStride; ++p)
        pixel_root_values(SimdLevel::scalar, t.data(), mag.data(), n1, dx + p, dy + p, want.data() + p, kStride,
                          want_e.data() + p, units, tiny);
      for (const SimdLevel l : levels()) {
        std::vector<double> got(want.size(), 1.5), got_e(kStride, 1.5);
        for (int p = 0; p < kStride; p += simd_lanes(l))
          pixel_root_values(l, t.data(), mag.data(), n1, dx + p, dy + p, got.data() + p, kStride, got_e.data() + p,
                            units, tiny);
        EXPECT_EQ(std::memcmp(got.data(), want.data(), want.size() * sizeof(double)), 0)
            << simd_name(l) << ", n1 = " << n1 << ", trial " << trial;
        EXPECT_EQ(std::memcmp(got_e.data(), want_e.data(), want_e.size() * sizeof(double)), 0)
            << simd_name(l) << ", n1 = " << n1 << ", trial " << trial;
        ++compared;
        if (l == SimdLevel::scalar) continue;
        // A wrong batch is visible here: the fault hook negates lane 1's v[0].
        const Fault fault;
        pixel_root_values(l, t.data(), mag.data(), n1, dx, dy, got.data(), kStride, got_e.data(), units, tiny);
        if (want[1] != 0) {
          EXPECT_EQ(got[1], -want[1]) << simd_name(l);
        }
      }
    }
  }
  EXPECT_GE(compared, 6 * 50 * 2);
}

RegionRequest request(int point, int depth, int size, std::optional<View> view, bool depth_map, Mode mode) {
  return test::region_request(point, depth, size, view, depth_map, mode);
}

struct Scene {
  std::string name;
  BSpline spline;
  int point;
};

std::vector<Scene> scenes() {
  return {{"cubic Bezier fig2 P1", read_spline_file(kSource + "/examples/figures/fig2.json"), 1},
          {"uniform cubic fig8 P3", read_spline_file(kSource + "/examples/figures/fig8.json"), 3},
          {"quartic Bezier P1", BSpline::bezier({{0, 0}, {2, 0}, {4, 1}, {5, 3}, {5, 5}}), 1},
          {"degree-9 Bezier P4", read_spline_file(kSource + "/examples/bezier9.json"), 4},
          {"rational cubic P3", read_spline_file(kSource + "/examples/rational/nurbs_cubic.json"), 3}};
}

// The views of a scene: its default view and two seeded zooms onto a region
// boundary (widths 1e-4 .. 0.2 of a unit, centres within a quarter width).
std::vector<std::optional<View>> views(const Scene& sc, int depth, Mode mode, std::mt19937_64& rng) {
  std::vector<std::optional<View>> out{std::nullopt};
  const auto edge =
      test::boundary_point(RegionProblem::make(sc.spline, request(sc.point, depth, 64, std::nullopt, false, mode)), 64);
  if (!edge) return out;
  std::uniform_real_distribution<double> log_width(std::log(1e-4), std::log(2e-1)), shift(-0.25, 0.25);
  for (int zoom = 0; zoom < 2; ++zoom) {
    const double w = std::exp(log_width(rng));
    const Vec2 c{edge->x + shift(rng) * w, edge->y + shift(rng) * w};
    out.push_back(View{c.x - w / 2, c.y - w / 2, c.x + w / 2, c.y + w / 2});
  }
  return out;
}

std::string describe(const Scene& sc, Mode mode, int depth, const std::optional<View>& v, bool depth_map) {
  std::ostringstream s;
  s.precision(17);
  s << sc.name << (mode == Mode::cmr ? ", CMR" : ", CMRWI") << ", D = " << depth;
  if (v) s << ", view [" << v->x0 << ", " << v->y0 << "] - [" << v->x1 << ", " << v->y1 << "]";
  else s << ", default view";
  s << (depth_map ? ", depth map" : ", labels only");
  return s.str();
}

// Pixels where two renders differ (labels or depths), with the first few named.
int differences(const RegionImage& a, const RegionImage& b, std::ostringstream& first) {
  int wrong = 0;
  for (std::size_t at = 0; at < a.labels.size(); ++at)
    if ((a.labels[at] != b.labels[at] || a.depth[at] != b.depth[at]) && wrong++ < 3)
      first << "\n  pixel (" << at % a.width << ", " << at / a.width << "): code " << int(a.labels[at]) << " depth "
            << int(a.depth[at]) << " vs code " << int(b.labels[at]) << " depth " << int(b.depth[at]);
  return wrong;
}

// One scene: every level's maps against the scalar level's and the exact
// path's; returns the pixels a faulty batch changed (the fault hook on).
std::uint64_t check_scene(const Scene& sc, unsigned seed, int size = 20) {
  std::mt19937_64 rng(seed);
  std::uint64_t faulty_differences = 0;
  std::vector<std::uint64_t> batched(3, 0);
  for (const Mode mode : {Mode::cmrwi, Mode::cmr})
    for (const int depth : {10, 16})
      for (const std::optional<View>& v : views(sc, depth, mode, rng))
        for (const bool depth_map : {false, true}) {
          const RegionProblem p = RegionProblem::make(sc.spline, request(sc.point, depth, size, v, depth_map, mode));
          const RegionSetup& s = p.setup();
          const std::string where = describe(sc, mode, depth, v, depth_map) + ", seed " + std::to_string(seed);
          RegionImage scalar;
          {
            const ForcedLevel forced(SimdLevel::scalar);
            scalar = region_cpu(s, 2);
          }
          // The exact path, pixel by pixel (no depths without a depth map).
          RegionImage exact = scalar;
          for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i) {
              const PixelResult r = classify_position_exact(s, pixel_center(p.view(), size, size, i, j));
              const std::size_t at = static_cast<std::size_t>(j) * size + i;
              exact.labels[at] = r.label;
              exact.depth[at] = depth_map ? r.depth : 0;
            }
          std::ostringstream first;
          EXPECT_EQ(differences(scalar, exact, first), 0) << "scalar vs exact: " << where << first.str();
          for (const SimdLevel l : levels()) {
            const ForcedLevel forced(l);
            const std::uint64_t before = simd_pixel_count(l);
            const RegionImage img = region_cpu(s, 2);
            batched[static_cast<int>(l)] += simd_pixel_count(l) - before;
            std::ostringstream diff;
            EXPECT_EQ(differences(img, scalar, diff), 0) << simd_name(l) << " vs scalar: " << where << diff.str();
            if (l == SimdLevel::scalar) continue;
            const Fault fault;
            std::ostringstream ignored;
            faulty_differences += differences(region_cpu(s, 2), scalar, ignored);
          }
        }
  // Every level compared pixels that went through its batch path.
  for (const SimdLevel l : levels())
    EXPECT_GT(batched[static_cast<int>(l)], 0u) << sc.name << ": no pixel went through " << simd_name(l);
  return faulty_differences;
}

// A wrong batch changes some pixel's label or depth, and the comparison
// would name it (where the CPU has a SIMD level).
void expect_fault_seen(std::uint64_t faulty_differences) {
  if (levels().size() > 1) {
    EXPECT_GT(faulty_differences, 0u);
  }
}

// Issue 39 item 4: at the AVX2 level the pixels of a small block go through
// Algorithm 1 in lock step (region/pixel_lanes.hpp). Their label and depth
// maps must be those of one pixel at a time, bit for bit, with and without
// the block records (labels only; a depth map has none), and the lock step
// must have run (PixelSimdMaps above compares the AVX2 level, lock step
// included, with the scalar level on every scene too).
struct LanesOff {
  LanesOff() { detail::set_pixel_lanes(0); }
  ~LanesOff() { detail::set_pixel_lanes(-1); }
};
// split_lanes is FlatPiecesN<N>::split (region.cpp) at each lane, bit for
// bit: its bound update written out here as there, its halving
// halve_in_pairs<N>; values of every kind (signed zeros, subnormals, huge,
// NaN in one lane).
template <int N>
void expect_split_bit_for_bit(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> exponent(-1070, 1000), kind(0, 9);
  detail::PixelLaneValues cur[N], right[N], e;
  double want_cur[detail::kPixelLanes][N], want_right[detail::kPixelLanes][N], want_e[detail::kPixelLanes];
  for (int l = 0; l < detail::kPixelLanes; ++l) {
    for (int k = 0; k < N; ++k) {
      const int c = kind(rng);
      const double x = c == 0 ? 0.0 : c == 1 ? -0.0 : c == 2 ? std::ldexp(unit(rng), -1060) : std::ldexp(unit(rng), exponent(rng) / 8);
      cur[k][l] = want_cur[l][k] = x;
    }
    if (l == 3) cur[N / 2][l] = want_cur[l][N / 2] = std::nan("");
    e[l] = want_e[l] = std::ldexp(std::fabs(unit(rng)), -40);
    double mag = 0;  // FlatPiecesN<N>::split, line by line
    for (int k = 0; k < N; ++k) mag = std::max(mag, std::fabs(want_cur[l][k]));
    want_e[l] += N * (0.5 * Bounded::kRound) * mag * (1 + 0x1p-20) + Bounded::kTiny;
    halve_in_pairs<N>(want_cur[l], want_right[l]);
  }
  detail::split_lanes<N>(cur, e, right);
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  for (int l = 0; l < detail::kPixelLanes; ++l) {
    EXPECT_TRUE(same(e[l], want_e[l])) << "N = " << N << ", lane " << l << ": bound " << e[l] << " vs " << want_e[l];
    for (int k = 0; k < N; ++k) {
      EXPECT_TRUE(same(cur[k][l], want_cur[l][k])) << "N = " << N << ", lane " << l << ", left " << k;
      EXPECT_TRUE(same(right[k][l], want_right[l][k])) << "N = " << N << ", lane " << l << ", right " << k;
    }
  }
}
TEST(PixelLanes, SplitIsFlatPiecesSplitBitForBit) {
  if (!simd_available(SimdLevel::avx2)) GTEST_SKIP() << "this CPU has no AVX2: the lock step does not run";
  std::mt19937_64 rng(3940);
  for (int round = 0; round < 200; ++round) {
    expect_split_bit_for_bit<6>(rng);
    expect_split_bit_for_bit<10>(rng);
    expect_split_bit_for_bit<30>(rng);
  }
}

TEST(PixelLanes, LockStepGivesTheMapsOfOnePixelAtATime) {
  if (!simd_available(SimdLevel::avx2)) GTEST_SKIP() << "this CPU has no AVX2: the lock step does not run";
  const ForcedLevel forced(SimdLevel::avx2);
  std::mt19937_64 rng(3939);
  std::uint64_t lanes = 0;
  int renders = 0;
  for (const int scene : {0, 1, 3})
    for (const int depth : {10, 16}) {
      const Scene sc = scenes()[static_cast<std::size_t>(scene)];
      for (const std::optional<View>& v : views(sc, depth, Mode::cmrwi, rng))
        for (const bool depth_map : {false, true}) {
          const RegionProblem p = RegionProblem::make(sc.spline, request(sc.point, depth, 32, v, depth_map, Mode::cmrwi));
          RegionImage alone;
          {
            const LanesOff off;
            alone = region_cpu(p.setup(), 2);
          }
          const std::uint64_t before = detail::pixel_lane_traversals.load();
          const RegionImage together = region_cpu(p.setup(), 2);
          lanes += detail::pixel_lane_traversals.load() - before;
          std::ostringstream diff;
          EXPECT_EQ(differences(together, alone, diff), 0)
              << describe(sc, Mode::cmrwi, depth, v, depth_map) << diff.str();
          ++renders;
        }
    }
  EXPECT_EQ(renders, 3 * 2 * 3 * 2);
  EXPECT_GT(lanes, 1000u) << "the lock step hardly ran";
}

TEST(PixelSimdMaps, CubicBezierAtEveryLevel) { expect_fault_seen(check_scene(scenes()[0], 2324)); }
TEST(PixelSimdMaps, UniformCubicAtEveryLevel) { expect_fault_seen(check_scene(scenes()[1], 2325)); }
TEST(PixelSimdMaps, QuarticBezierAtEveryLevel) { expect_fault_seen(check_scene(scenes()[2], 2326)); }
TEST(PixelSimdMaps, Degree9BezierAtEveryLevel) { expect_fault_seen(check_scene(scenes()[3], 2327, 12)); }
TEST(PixelSimdMaps, RationalCubicAtEveryLevel) { expect_fault_seen(check_scene(scenes()[4], 2328, 12)); }

}  // namespace
}  // namespace cmr
