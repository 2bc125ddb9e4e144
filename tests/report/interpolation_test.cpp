// g1-between-masters (report/interpolation.hpp) on hand-made tangents, and
// the pieces' parsing and user values (io/masters.hpp). The designspaces
// end to end: interpolation_sources (interpolation_test.py).
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "io/masters.hpp"
#include "report/gates.hpp"
#include "report/interpolation.hpp"
#include "spline/errors.hpp"

namespace cmr::report {
namespace {

NodeTangents tangents(double u0x, double u0y, double u1x, double u1y, double v0x, double v0y, double v1x,
                      double v1y) {
  return {Rational(u0x), Rational(u0y), Rational(u1x), Rational(u1y),
          Rational(v0x), Rational(v0y), Rational(v1x), Rational(v1y)};
}

/// The angle between u(s) and v(s) in degrees, in double (the test's own).
double angle(const double t[8], double s) {
  const double ux = (1 - s) * t[0] + s * t[2], uy = (1 - s) * t[1] + s * t[3];
  const double vx = (1 - s) * t[4] + s * t[6], vy = (1 - s) * t[5] + s * t[7];
  return std::abs(std::atan2(ux * vy - uy * vx, ux * vx + uy * vy)) * 180 / std::numbers::pi;
}

TEST(G1Between, HandlesInDifferentRatiosKinkStrictlyBetween) {
  // Regular: u = (100, 0), v = (200, 0) (ratio 2); Bold: u = (60, 30), v = (240, 120) (ratio 4).
  const double t[8] = {100, 0, 60, 30, 200, 0, 240, 120};
  const G1Between g = g1_between(tangents(t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7]));
  ASSERT_TRUE(g.judged);
  EXPECT_FALSE(g.holds);
  ASSERT_EQ(g.fail.size(), 1u);  // c = 6000 s (1 - s): a kink on all of (0, 1)
  EXPECT_EQ(g.fail[0].first, 0.0);
  EXPECT_EQ(g.fail[0].second, 1.0);
  EXPECT_GT(g.worst_s, 0.0);
  EXPECT_LT(g.worst_s, 1.0);
  // The worst angle is the largest on a fine grid (within the grid's resolution), and at worst_s.
  double best = 0;
  for (int k = 0; k <= 100000; ++k) best = std::max(best, angle(t, k / 100000.0));
  EXPECT_NEAR(g.worst_angle, best, 1e-6);
  EXPECT_NEAR(angle(t, g.worst_s), g.worst_angle, 1e-9);
}

TEST(G1Between, ProportionalHandlesHold) {
  // v = 2 u at both masters: v(s) = 2 u(s) for every s.
  const G1Between g = g1_between(tangents(100, 0, 60, 30, 200, 0, 120, 60));
  EXPECT_TRUE(g.judged);
  EXPECT_TRUE(g.holds);
  EXPECT_TRUE(g.fail.empty());
}

TEST(G1Between, CollinearThroughoutButReversingFails) {
  // v = (1, 0) throughout, u from (1, 0) to (-1, 0): collinear at every s, but u passes through 0 at s = 1/2
  // and reverses (a masters' pair the caller would not judge: it is not G1 at Bold; the polynomial test alone).
  const G1Between g = g1_between(tangents(1, 0, -1, 0, 1, 0, 1, 0));
  EXPECT_FALSE(g.holds);
  ASSERT_FALSE(g.fail.empty());
  EXPECT_EQ(g.worst_angle, 180);
  EXPECT_LE(g.fail[0].first, 0.5);
  EXPECT_GE(g.fail[0].second, 0.5);
}

TEST(G1Between, PartOfTheLineMayStartAtAKink) {
  // The kink's tangents restricted to s in [1/4, 3/4]: c != 0 at both ends, so the whole part fails, and the
  // worst angle is the line's (inside) or an end's.
  auto at = [](double a, double b, double s) { return (1 - s) * a + s * b; };
  const double t[8] = {100, 0, 60, 30, 200, 0, 240, 120};
  const double s0 = 0.25, s1 = 0.75;
  const double q[8] = {at(t[0], t[2], s0), at(t[1], t[3], s0), at(t[0], t[2], s1), at(t[1], t[3], s1),
                       at(t[4], t[6], s0), at(t[5], t[7], s0), at(t[4], t[6], s1), at(t[5], t[7], s1)};
  const G1Between g = g1_between(tangents(q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7]));
  EXPECT_FALSE(g.holds);
  ASSERT_EQ(g.fail.size(), 1u);
  EXPECT_EQ(g.fail[0].first, 0.0);
  EXPECT_EQ(g.fail[0].second, 1.0);
  double best = 0;
  for (int k = 0; k <= 100000; ++k) best = std::max(best, angle(q, k / 100000.0));
  EXPECT_NEAR(g.worst_angle, best, 1e-6);
}

TEST(G1Between, SmoothAtAnInstanceIsExact) {
  EXPECT_TRUE(g1_at(Rational(3), Rational(4), Rational(6), Rational(8)));
  EXPECT_FALSE(g1_at(Rational(3), Rational(4), Rational(-6), Rational(-8)));  // reversed
  // Off by the last bit of a double: not collinear in exact arithmetic.
  EXPECT_FALSE(g1_at(Rational(0.1), Rational(0.2), Rational(0.1), Rational(std::nextafter(0.2, 1.0))));
}

TEST(G1Between, WithinATurnFailsExactlyWhereTheTurnExceedsIt) {
  // Marked smooth but rounded to integers: 0.19 degrees off at Regular, 0.57 at Bold,
  // 19.4 degrees between (tools/bench/midway_compare.py's case "rounded").
  const double t[8] = {100, 0, 100, 100, 300, 1, 50, 51};
  const double deg = 1;
  const Rational T(std::tan(deg * std::numbers::pi / 180));
  const NodeTangents n = tangents(t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7]);
  // The exact rule does not judge it (not collinear at the masters); within 1 degree does.
  EXPECT_FALSE(g1_at(n.u0x, n.u0y, n.v0x, n.v0y));
  EXPECT_TRUE(g1_at(n.u0x, n.u0y, n.v0x, n.v0y, T));
  EXPECT_TRUE(g1_at(n.u1x, n.u1y, n.v1x, n.v1y, T));
  const G1Between g = g1_between(n, T);
  ASSERT_TRUE(g.judged);
  EXPECT_FALSE(g.holds);
  ASSERT_EQ(g.fail.size(), 1u);
  const auto [lo, hi] = g.fail[0];
  ASSERT_LT(lo, hi);
  // The interval's ends are where the turn is exactly 1 degree: above it inside, below it outside.
  EXPECT_NEAR(angle(t, lo), deg, 1e-6);
  EXPECT_NEAR(angle(t, hi), deg, 1e-6);
  EXPECT_GT(angle(t, (lo + hi) / 2), deg);
  EXPECT_LT(angle(t, lo / 2), deg);
  EXPECT_LT(angle(t, (hi + 1) / 2), deg);
  // The worst instance: no sample has a larger turn.
  for (int k = 0; k <= 1000; ++k) EXPECT_LE(angle(t, k / 1000.0), g.worst_angle + 1e-9);
  EXPECT_NEAR(angle(t, g.worst_s), g.worst_angle, 1e-9);
  EXPECT_GT(g.worst_angle, 19);
  // A turn larger than the node's worst: it holds; the proportional twin holds within any turn.
  EXPECT_TRUE(g1_between(n, Rational(std::tan(20 * std::numbers::pi / 180))).holds);
  EXPECT_TRUE(g1_between(tangents(100, 0, 60, 30, 200, 0, 120, 60), T).holds);
}

TEST(G1BetweenFix, SmallestGridMoveInOneMasterMakesTheNodeG1Throughout) {
  // The kink example (examples/interpolation): Regular u = (100, 0), v = (200, 0); Bold u = (60, 30), v = (240, 120).
  const Vec2 reg[3] = {{0, 0}, {-100, 0}, {200, 0}}, bold[3] = {{0, 0}, {-60, -30}, {240, 120}};
  for (int moved = 0; moved < 2; ++moved) {
    const Vec2* m = moved == 0 ? reg : bold;
    const Vec2* o = moved == 0 ? bold : reg;
    const Vec2 node[2] = {m[0], o[0]}, in[2] = {m[1], o[1]}, out[2] = {m[2], o[2]};
    const std::optional<G1NodeFix> f = g1_between_fix(node, in, out);
    ASSERT_TRUE(f) << moved;
    // Re-judged exactly: G1 at every location between, with the other master as it was.
    const Vec2 u = m[0] - f->in_handle, v = f->out_handle - m[0];
    const Vec2 uo = o[0] - o[1], vo = o[2] - o[0];
    const NodeTangents t = moved == 0 ? tangents(u.x, u.y, uo.x, uo.y, v.x, v.y, vo.x, vo.y)
                                      : tangents(uo.x, uo.y, u.x, u.y, vo.x, vo.y, v.x, v.y);
    EXPECT_TRUE(g1_between(t).holds) << moved;
    // On the grid, on the master's tangent line, and no nearer such fix (brute force over the grid's
    // points on the line: alpha, beta up to 400 steps of the primitive direction).
    EXPECT_EQ(f->in_handle.x, std::floor(f->in_handle.x));
    EXPECT_EQ(f->out_handle.y, std::floor(f->out_handle.y));
    const Vec2 g = moved == 0 ? Vec2{1, 0} : Vec2{2, 1};
    const double a0 = moved == 0 ? 100 : 30, b0 = moved == 0 ? 200 : 120;  // u = a0 g, v = b0 g
    double best = 1e300;
    for (int a = 1; a <= 400; ++a)
      for (int b = 1; b <= 400; ++b) {
        const NodeTangents c = moved == 0 ? tangents(a * g.x, a * g.y, uo.x, uo.y, b * g.x, b * g.y, vo.x, vo.y)
                                          : tangents(uo.x, uo.y, a * g.x, a * g.y, vo.x, vo.y, b * g.x, b * g.y);
        // c1 == 0 exactly (the cross product's middle coefficient; the ends are 0): G1 throughout.
        if (c.u0x * c.v1y - c.u0y * c.v1x + c.u1x * c.v0y - c.u1y * c.v0x != 0) continue;
        best = std::min(best, (std::abs(a - a0) + std::abs(b - b0)) * std::hypot(g.x, g.y));
      }
    EXPECT_NEAR(f->distance, best, 1e-9) << moved;
  }
  // Fixing Regular moves least: its incoming handle from (-100, 0) to (-50, 0) (ratio 1:4 as Bold's).
  const Vec2 node[2] = {reg[0], bold[0]}, in[2] = {reg[1], bold[1]}, out[2] = {reg[2], bold[2]};
  const std::optional<G1NodeFix> f = g1_between_fix(node, in, out);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->in_handle, Vec2(-50, 0));
  EXPECT_EQ(f->out_handle, Vec2(200, 0));
  EXPECT_DOUBLE_EQ(f->distance, 50);
  // Refused: a non-integer coordinate, a node not G1 at a master, a handle of zero length.
  const Vec2 off[2] = {{-100.5, 0}, bold[1]}, bent[2] = {{-100, 1}, bold[1]}, zero[2] = {{0, 0}, bold[1]};
  EXPECT_FALSE(g1_between_fix(node, off, out));
  EXPECT_FALSE(g1_between_fix(node, bent, out));
  EXPECT_FALSE(g1_between_fix(node, zero, out));
  // Already G1 between (the proportional twin): unmoved.
  const Vec2 pin[2] = {reg[1], {-60, -30}}, pout[2] = {reg[2], {120, 60}};
  const std::optional<G1NodeFix> same = g1_between_fix(node, pin, pout);
  ASSERT_TRUE(same);
  EXPECT_EQ(same->distance, 0.0);
  EXPECT_EQ(same->in_handle, reg[1]);
}

// A node with a line on one side (its "handle" there is the line's other end,
// which stays): only the other handle moves, to the length that gives the
// other master's ratio; refused when that length is not on the grid. Checked
// against a brute force over the free handle's grid points on its tangent.
TEST(G1BetweenFix, ALinesSideKeepsItsLengthAndTheHandleTakesTheRatio) {
  // Regular: line from (-300, 0), handle (200, 0); Bold: line from (-180, -90), handle (240, 120).
  const Vec2 node[2] = {{0, 0}, {0, 0}}, line[2] = {{-300, 0}, {-180, -90}}, handle[2] = {{200, 0}, {240, 120}};
  const std::optional<G1NodeFix> f = g1_between_fix(node, line, handle, true, false);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->in_handle, Vec2(-300, 0));  // the line's end stays
  EXPECT_EQ(f->out_handle, Vec2(400, 0));  // 300 : 400 = 90 : 120
  EXPECT_DOUBLE_EQ(f->distance, 200);
  // Brute force: the free handle at (b, 0), b = 1..1000, G1 throughout iff u0 x v1 + u1 x v0 == 0 (exact in doubles).
  int passing = 0;
  for (int b = 1; b <= 1000; ++b) {
    const double c = 300.0 * 120 - 0.0 * 240 + 180.0 * 0 - 90.0 * b;  // (300,0)x(240,120) + (180,90)x(b,0)
    if (c != 0) continue;
    ++passing;
    EXPECT_EQ(b, 400);
  }
  EXPECT_EQ(passing, 1);
  // Moving Bold's handle instead: 90 : beta = 300 : 200, beta = 60 units of (2, 1).
  const Vec2 node_b[2] = {node[1], node[0]}, line_b[2] = {line[1], line[0]}, handle_b[2] = {handle[1], handle[0]};
  const std::optional<G1NodeFix> fb = g1_between_fix(node_b, line_b, handle_b, true, false);
  ASSERT_TRUE(fb);
  EXPECT_EQ(fb->out_handle, Vec2(120, 60));
  EXPECT_NEAR(fb->distance, std::hypot(120.0, 60.0), 1e-12);
  // The line on the outgoing side: the same by symmetry.
  const Vec2 in_h[2] = {{-200, 0}, {-240, -120}}, line_out[2] = {{300, 0}, {180, 90}};
  const std::optional<G1NodeFix> fo = g1_between_fix(node, in_h, line_out, false, true);
  ASSERT_TRUE(fo);
  EXPECT_EQ(fo->in_handle, Vec2(-400, 0));
  EXPECT_EQ(fo->out_handle, Vec2(300, 0));
  // Bold's line 7 units of (2, 1): 300 * 120 / 7 and 7 * 200 / 300 are no integers: refused both ways.
  const Vec2 odd[2] = {{-300, 0}, {-14, -7}}, odd_b[2] = {odd[1], odd[0]};
  EXPECT_FALSE(g1_between_fix(node, odd, handle, true, false));
  EXPECT_FALSE(g1_between_fix(node_b, odd_b, handle_b, true, false));
  // Lines on both sides: only a node already G1 throughout passes (unmoved).
  EXPECT_FALSE(g1_between_fix(node, line, handle, true, true));
  const Vec2 prop[2] = {{200, 0}, {120, 60}};
  const std::optional<G1NodeFix> both = g1_between_fix(node, line, prop, true, true);
  ASSERT_TRUE(both);
  EXPECT_EQ(both->distance, 0.0);
}

// g1-between-masters:DEG's tangent-ray family: each handle of master 0 on the
// ray of master 1's tangent (the grid point nearest it); the turn is then
// master 1's at every location, so within 1 degree when it is so there.
TEST(G1BetweenFix, HandlesOnTheOtherMastersTangentsKeepItsTurnThroughout) {
  const Vec2 node[2] = {{0, 0}, {0, 0}}, in[2] = {{-100, 0}, {-100, -100}}, out[2] = {{300, 1}, {50, 51}};
  const std::optional<G1NodeFix> f = parallel_turn_fix(node, in, out);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->in_handle, Vec2(-50, -50));  // nearest multiple of (1, 1) to (-100, 0): 50
  EXPECT_EQ(f->out_handle, Vec2(150, 153));  // round(15051 / 5101) = 3 times (50, 51)
  EXPECT_NEAR(f->distance, std::hypot(50.0, 50.0) + std::hypot(150.0, 152.0), 1e-9);
  const Rational T(std::tan(std::numbers::pi / 180));
  auto tangents = [&](Vec2 in0, Vec2 out0) {
    return NodeTangents{Rational(-in0.x), Rational(-in0.y), Rational(100), Rational(100),
                        Rational(out0.x), Rational(out0.y), Rational(50), Rational(51)};
  };
  EXPECT_FALSE(g1_between(tangents(in[0], out[0]), T).holds);  // 19 degrees between before
  EXPECT_TRUE(g1_between(tangents(f->in_handle, f->out_handle), T).holds);
  const Vec2 frac[2] = {{-100.5, 0}, in[1]};
  EXPECT_FALSE(parallel_turn_fix(node, frac, out));  // off the grid: refused
}

// g1_least_move against brute force: every pair of grid positions of the
// moving master's two handles in a box around them, judged by the test's own
// criterion (the cross product's Bernstein coefficients all zero, and the
// dot product d(s) > 0 on [0, 1]: at both ends and at its vertex when that
// lies inside), not by the header's derivation. The least passing total
// move in the box equals g1_least_move's whenever that lies within the box.
namespace least {

struct V {
  long long x, y;
};
long long cr(V a, V b) { return a.x * b.y - a.y * b.x; }
long long dt(V a, V b) { return a.x * b.x + a.y * b.y; }

/// G1 at every s in [0, 1] for u(s) = (1 - s) u0 + s u1, v(s) likewise.
bool g1_throughout(V u0, V v0, V u1, V v1) {
  if (cr(u0, v0) != 0 || cr(u1, v1) != 0 || cr(u0, v1) + cr(u1, v0) != 0) return false;
  const double d0 = static_cast<double>(dt(u0, v0)), d1 = (dt(u0, v1) + dt(u1, v0)) / 2.0, d2 = static_cast<double>(dt(u1, v1));
  if (!(d0 > 0 && d2 > 0)) return false;
  const double a = d0 - 2 * d1 + d2;  // d(s) = d0 (1-s)^2 + 2 d1 s (1-s) + d2 s^2 = a s^2 + 2 (d1 - d0) s + d0
  if (a > 0) {
    const double s = (d0 - d1) / a;
    if (s > 0 && s < 1 && a * s * s + 2 * (d1 - d0) * s + d0 <= 0) return false;
  }
  return true;
}

double len(V a, V b) { return std::hypot(static_cast<double>(a.x - b.x), static_cast<double>(a.y - b.y)); }

}  // namespace least

TEST(G1LeastMove, TheLeastOverEveryGridPositionOfBothHandles) {
  using least::V;
  std::mt19937 rng(37);
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  auto dir = [&] {
    V g{0, 0};
    while (g.x == 0 && g.y == 0) g = {pick(-2, 2), pick(-2, 2)};
    return g;
  };
  int compared = 0, moved = 0, rotated = 0;
  for (int trial = 0; trial < 160; ++trial) {
    // Master m: node (0, 0), u = a g, v = b g; one or two neighbours: u' = a' g', v' = b' g'.
    const V g = dir();
    const int a = pick(1, 4), b = pick(1, 4);
    const V u{a * g.x, a * g.y}, v{b * g.x, b * g.y};
    const int neighbours = trial % 4 == 3 ? 2 : 1;
    std::vector<std::pair<V, V>> others;
    for (int k = 0; k < neighbours; ++k) {
      const V h = trial % 5 == 0 ? g : dir();
      const int a1 = pick(1, 4), b1 = pick(1, 4);
      if (least::dt(h, g) < 0 && least::cr(h, g) == 0) continue;  // reversed: the gate judges nothing here
      others.push_back({{a1 * h.x, a1 * h.y}, {b1 * h.x, b1 * h.y}});
    }
    if (others.empty()) continue;
    const bool in_fixed = trial % 7 == 1, out_fixed = trial % 7 == 2;
    G1NodeRule rule{{0, 0}, {static_cast<double>(-u.x), static_cast<double>(-u.y)},
                    {static_cast<double>(v.x), static_cast<double>(v.y)}, in_fixed, out_fixed, {}, true};
    // Every third trial the neighbour's tangents halved (u' / 2, v' / 2: off the grid, as a master's points
    // may be): the same direction and ratio, so the same answer (its instances are the integer pair's,
    // reparametrised: (1 - s) u + s u' / 2 is a positive multiple of (1 - t) u + t u', t = s / (2 - s), and v
    // likewise with the same t). The brute force keeps the integer pair.
    const double scale = trial % 3 == 0 ? 0.5 : 1.0;
    for (const auto& [uo, vo] : others)
      rule.others.push_back({scale * Vec2(static_cast<double>(uo.x), static_cast<double>(uo.y)),
                             scale * Vec2(static_cast<double>(vo.x), static_cast<double>(vo.y))});
    const std::optional<G1LeastMove> f = g1_least_move({rule});
    // Brute force: u2, v2 in a box of 12 around u, v (a line's side stays).
    const int box = 12;
    double brute = std::numeric_limits<double>::infinity();
    for (int ux = -box; ux <= box; ++ux)
      for (int uy = -box; uy <= box; ++uy) {
        if (in_fixed && (ux != 0 || uy != 0)) continue;
        const V u2{u.x + ux, u.y + uy};
        for (int vx = -box; vx <= box; ++vx)
          for (int vy = -box; vy <= box; ++vy) {
            if (out_fixed && (vx != 0 || vy != 0)) continue;
            const V v2{v.x + vx, v.y + vy};
            bool ok = true;
            for (const auto& [uo, vo] : others) ok = ok && least::g1_throughout(u2, v2, uo, vo);
            if (ok) brute = std::min(brute, least::len(u2, u) + least::len(v2, v));
          }
      }
    if (f && f->distance < box) {
      EXPECT_NEAR(f->distance, brute, 1e-9) << "trial " << trial;
      ++compared;
      moved += f->distance > 0;
      // Its answer passes the test's own criterion, on the grid.
      const G1NodeFix& h = f->nodes.at(0);
      const V u2{static_cast<long long>(-h.in_handle.x), static_cast<long long>(-h.in_handle.y)};
      const V v2{static_cast<long long>(h.out_handle.x), static_cast<long long>(h.out_handle.y)};
      EXPECT_EQ(h.in_handle.x, std::floor(h.in_handle.x));
      for (const auto& [uo, vo] : others) EXPECT_TRUE(least::g1_throughout(u2, v2, uo, vo)) << "trial " << trial;
      rotated += least::cr(u2, u) != 0;
    } else {
      EXPECT_GE(brute, f ? f->distance - 1e-9 : box) << "trial " << trial;  // nothing cheaper in the box
    }
  }
  EXPECT_GT(compared, 100);
  EXPECT_GT(moved, 60);
  std::printf("compared %d, moved %d, off the old tangent %d\n", compared, moved, rotated);
  EXPECT_GT(rotated, 10);  // answers outside the master's own tangent line (the family searched before)
}

// The case the tangent-keeping family missed: master m's tangent one unit
// off the neighbour's (u = (100, 1)). Keeping it, the handles must take the
// ratio 1:4 along (100, 1) (u = (100, 1), v = (400, 4): 200 units); turned
// onto the neighbour's tangent with its own lengths, 1 + 2 = 3 units.
TEST(G1LeastMove, TurningTheTangentOntoTheNeighboursCanBeCheapest) {
  const G1NodeRule rule{{0, 0}, {-100, -1}, {200, 2}, false, false, {{Vec2{100, 0}, Vec2{400, 0}}}, true};
  const std::optional<G1LeastMove> f = g1_least_move({rule});
  ASSERT_TRUE(f);
  EXPECT_EQ(f->nodes[0].in_handle, Vec2(-100, 0));
  EXPECT_EQ(f->nodes[0].out_handle, Vec2(200, 0));
  EXPECT_DOUBLE_EQ(f->distance, 3);
  const Vec2 node[2] = {{0, 0}, {0, 0}}, in[2] = {{-100, -1}, {-100, 0}}, out[2] = {{200, 2}, {400, 0}};
  const std::optional<G1NodeFix> kept = g1_between_fix(node, in, out);
  ASSERT_TRUE(kept);
  EXPECT_NEAR(kept->distance, std::hypot(200.0, 2.0), 1e-9);  // v from (200, 2) to (400, 4)
  // Refused: off the grid, a zero tangent at the neighbour.
  G1NodeRule off = rule;
  off.in_handle = {-100.5, -1};
  EXPECT_FALSE(g1_least_move({off}));
  G1NodeRule zero = rule;
  zero.others = {{Vec2{0, 0}, Vec2{400, 0}}};
  EXPECT_FALSE(g1_least_move({zero}));
}

// Two nodes sharing a handle (a quadratic source's off-curve point between
// two smooth on-curve points): searched together, against brute force over
// the shared point and both other handles in a box.
TEST(G1LeastMove, TwoNodesSharingAHandleAreSearchedTogether) {
  using least::V;
  std::mt19937 rng(3700);
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  int compared = 0;
  for (int trial = 0; trial < 12; ++trial) {
    // Node A at (0, 0): in-handle -a g, shared handle h = b g; node B = h + c k, out-handle B + e k.
    const V g{pick(1, 2), pick(-1, 1)}, k{pick(-1, 1), pick(1, 2)};
    const int a = pick(1, 3), b = pick(1, 3), c = pick(1, 3), e = pick(1, 3);
    const V A{0, 0}, ha{-a * g.x, -a * g.y}, h{b * g.x, b * g.y}, B{h.x + c * k.x, h.y + c * k.y}, hb{B.x + e * k.x, B.y + e * k.y};
    // The neighbour master: each node's tangents along other directions, in other ratios.
    const V go{g.x + 1, g.y}, ko{k.x, k.y + 1};
    const int ra = pick(1, 3), rb = pick(1, 3);
    const std::pair<V, V> oa{{go.x, go.y}, {ra * go.x, ra * go.y}}, ob{{ko.x, ko.y}, {rb * ko.x, rb * ko.y}};
    auto vec = [](V p) { return Vec2(static_cast<double>(p.x), static_cast<double>(p.y)); };
    const G1NodeRule ra_rule{vec(A), vec(ha), vec(h), false, false, {{vec(oa.first), vec(oa.second)}}, true};
    const G1NodeRule rb_rule{vec(B), vec(h), vec(hb), false, false, {{vec(ob.first), vec(ob.second)}}, true};
    const std::optional<G1LeastMove> f = g1_least_move({ra_rule, rb_rule});
    const int box = 5;
    double brute = std::numeric_limits<double>::infinity();
    for (int x0 = -box; x0 <= box; ++x0)
      for (int y0 = -box; y0 <= box; ++y0) {
        const V ha2{ha.x + x0, ha.y + y0};
        const V ua{A.x - ha2.x, A.y - ha2.y};
        for (int x1 = -box; x1 <= box; ++x1)
          for (int y1 = -box; y1 <= box; ++y1) {
            const V h2{h.x + x1, h.y + y1};
            const V va{h2.x - A.x, h2.y - A.y}, ub{B.x - h2.x, B.y - h2.y};
            if (!least::g1_throughout(ua, va, oa.first, oa.second)) continue;
            for (int x2 = -box; x2 <= box; ++x2)
              for (int y2 = -box; y2 <= box; ++y2) {
                const V hb2{hb.x + x2, hb.y + y2};
                if (!least::g1_throughout(ub, V{hb2.x - B.x, hb2.y - B.y}, ob.first, ob.second)) continue;
                brute = std::min(brute, least::len(ha2, ha) + least::len(h2, h) + least::len(hb2, hb));
              }
          }
      }
    if (f && f->distance < box) {
      EXPECT_NEAR(f->distance, brute, 1e-9) << "trial " << trial;
      EXPECT_EQ(f->nodes[0].out_handle, f->nodes[1].in_handle);  // the shared point, once
      ++compared;
    } else {
      EXPECT_GE(brute, f ? f->distance - 1e-9 : box) << "trial " << trial;
    }
  }
  EXPECT_GE(compared, 4);
  std::printf("pairs compared with brute force: %d of 12\n", compared);
}

// Runs of three nodes joined by shared handles, and closed rings of three
// (a TrueType contour whose every on-curve point is smooth and every
// off-curve point lies between two of them), against brute force over every
// handle's grid positions in a box, pruned node by node.
TEST(G1LeastMove, RunsAndRingsOfSharedHandlesAgainstBruteForce) {
  using least::V;
  std::mt19937 rng(373);
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  auto vec = [](V p) { return Vec2(static_cast<double>(p.x), static_cast<double>(p.y)); };
  int compared = 0, total = 0;
  for (int trial = 0; trial < 80; ++trial) {
    const bool closed = trial % 2 == 1;
    // Handles h0..h3 (h3 = h0 on a ring); node i on the segment h_i -> h_{i+1} at a grid point strictly inside.
    std::vector<V> h;
    std::vector<V> node;
    bool ok = true;
    h.push_back({pick(-4, 4), pick(-4, 4)});
    for (int i = 0; i < 3 && ok; ++i) {
      const V a = h.back();
      V b{};
      if (closed && i == 2) {
        b = h[0];
      } else {
        const V step{pick(-2, 2), pick(-2, 2)};
        const int n = pick(2, 4);
        b = {a.x + n * step.x, a.y + n * step.y};
        if (step.x == 0 && step.y == 0) ok = false;
      }
      const long long g = std::gcd(std::llabs(b.x - a.x), std::llabs(b.y - a.y));
      if (g < 2) {
        ok = false;
        break;
      }
      const long long t = pick(1, static_cast<int>(g) - 1);
      node.push_back({a.x + t * (b.x - a.x) / g, a.y + t * (b.y - a.y) / g});
      if (!(closed && i == 2)) h.push_back(b);
    }
    if (!ok) continue;
    const std::size_t k = 3, handles = closed ? 3 : 4;
    auto H = [&](const std::vector<V>& hs, std::size_t i) { return hs[i % handles]; };
    // Each node's neighbour: its own tangent or another direction, in a random ratio.
    std::vector<std::pair<V, V>> other;
    std::vector<G1NodeRule> rules;
    for (std::size_t i = 0; i < k; ++i) {
      const V u{node[i].x - H(h, i).x, node[i].y - H(h, i).y};
      const long long g = std::gcd(std::llabs(u.x), std::llabs(u.y));
      V d{u.x / g, u.y / g};
      if (pick(0, 2) != 0) d = {d.x + pick(-1, 1), d.y + pick(0, 1)};
      if (d.x == 0 && d.y == 0) d = {1, 0};
      // The neighbour's ratio: the node's own (v / u along its segment) or 1:1, 1:2, 2:1.
      const V v{H(h, i + 1).x - node[i].x, H(h, i + 1).y - node[i].y};
      const long long gv = std::gcd(std::llabs(v.x), std::llabs(v.y));
      const int choice = pick(0, 3);
      const long long a1 = choice == 0 ? g : choice == 2 ? 2 : 1, b1 = choice == 0 ? gv : choice == 3 ? 2 : 1;
      other.push_back({{a1 * d.x, a1 * d.y}, {b1 * d.x, b1 * d.y}});
      rules.push_back({vec(node[i]), vec(H(h, i)), vec(H(h, i + 1)), false, false,
                       {{vec(other[i].first), vec(other[i].second)}}, true});
    }
    const std::optional<G1LeastMove> f = g1_least_move(rules, closed, 64);  // reach: beyond the box is enough
    // Brute force: handles in a box of 3 around theirs, node i judged once h_i and h_{i+1} are placed.
    const int box = 3;
    double brute = std::numeric_limits<double>::infinity();
    std::vector<V> cur(handles);
    std::function<void(std::size_t, double)> place = [&](std::size_t j, double cost) {
      if (cost >= brute) return;
      if (j == handles) {
        if (closed) {  // the last node closes on h0
          const V u{node[2].x - cur[2].x, node[2].y - cur[2].y}, v{cur[0].x - node[2].x, cur[0].y - node[2].y};
          if (!least::g1_throughout(u, v, other[2].first, other[2].second)) return;
        }
        brute = cost;
        return;
      }
      for (int dx = -box; dx <= box; ++dx)
        for (int dy = -box; dy <= box; ++dy) {
          cur[j] = {h[j].x + dx, h[j].y + dy};
          if (j >= 1) {  // node j - 1 has both handles now
            const V u{node[j - 1].x - cur[j - 1].x, node[j - 1].y - cur[j - 1].y}, v{cur[j].x - node[j - 1].x, cur[j].y - node[j - 1].y};
            if (!least::g1_throughout(u, v, other[j - 1].first, other[j - 1].second)) continue;
          }
          place(j + 1, cost + std::hypot(static_cast<double>(dx), static_cast<double>(dy)));
        }
    };
    place(0, 0);
    ++total;
    if (f && f->distance < box) {
      EXPECT_NEAR(f->distance, brute, 1e-9) << "trial " << trial << (closed ? " ring" : " run");
      for (std::size_t i = 0; i + 1 < k; ++i) EXPECT_EQ(f->nodes[i].out_handle, f->nodes[i + 1].in_handle);
      if (closed) {
        EXPECT_EQ(f->nodes[2].out_handle, f->nodes[0].in_handle);
      }
      ++compared;
    } else {
      EXPECT_GE(brute, f ? f->distance - 1e-9 : box) << "trial " << trial << (closed ? " ring" : " run");
    }
  }
  std::printf("runs and rings compared with brute force: %d of %d\n", compared, total);
  EXPECT_GE(compared, 16);
}

TEST(InterpolationGate, ParsesWithATurnOnlyForG1) {
  const std::optional<Gate> g = parse_gate("g1-between-masters");
  ASSERT_TRUE(g);
  EXPECT_EQ(g->kind, Gate::Kind::g1_between_masters);
  EXPECT_EQ(g->turn_degrees, 0.0);
  EXPECT_TRUE(is_interpolation_gate(*g));
  EXPECT_EQ(to_string(*g), "g1-between-masters");
  const std::optional<Gate> t = parse_gate("g1-between-masters:0.5");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->turn_degrees, 0.5);
  EXPECT_EQ(to_string(*t), "g1-between-masters:0.5");
  EXPECT_EQ(to_string(*parse_gate("g1-between-masters:0")), "g1-between-masters");
  for (const char* bad : {"g1-between-masters:", "g1-between-masters:x", "g1-between-masters:-1",
                          "g1-between-masters:90", "g1-between-masters:nan", "curvature-between-masters:2"})
    EXPECT_THROW(parse_gate(bad), InputError) << bad;
  for (const char* name : {"curvature-between-masters", "extrema-between-masters"}) {
    const std::optional<Gate> c = parse_gate(name);
    ASSERT_TRUE(c) << name;
    EXPECT_TRUE(is_interpolation_gate(*c));
    EXPECT_EQ(to_string(*c), name);
  }
  EXPECT_FALSE(is_interpolation_gate(*parse_gate("g2-at-smooth-nodes")));
}

TEST(Pieces, BetweenParsesTwoLocations) {
  const import::Segment2 s = import::parse_between("wght=400:wght=700,wdth=100");
  ASSERT_EQ(s.first.size(), 1u);
  ASSERT_EQ(s.second.size(), 2u);
  EXPECT_EQ(s.second[1].first, "wdth");
  EXPECT_THROW(import::parse_between("wght=400"), InputError);
  EXPECT_THROW(import::parse_between("wght=400:wght=x"), InputError);
  EXPECT_THROW(import::parse_between("a:b:c"), InputError);
  try {
    import::parse_between("wght=400:weight=700");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("between:", 0), 0u) << e.what();  // the field: --between in cmr
  }
}

TEST(Pieces, UserValuesFollowTheBreaks) {
  import::Piece p;
  p.axes.push_back({"Weight", "wght", {{0.0, 400.0}, {0.5, 500.0}, {1.0, 700.0}}});
  p.axes.push_back({"Width", "wdth", {{0.0, 100.0}}});
  EXPECT_DOUBLE_EQ(p.axes[0].user(0.25), 450);
  EXPECT_DOUBLE_EQ(p.axes[0].user(0.75), 600);
  EXPECT_EQ(p.location(0.75), "\"Weight\": 600, \"Width\": 100");
  EXPECT_EQ(p.range(0, 0.5), "Weight in (400, 500)");
}

}  // namespace
}  // namespace cmr::report
