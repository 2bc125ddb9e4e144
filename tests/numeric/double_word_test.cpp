// DoubleWord (numeric/double_word.hpp), the second filter of a joint's
// curvature, against exact rationals: on seeded random expressions the exact
// value always lies within the bound, truncated() is mpq_get_d of the exact
// value whenever it answers (and answers for most), and certain_sign never
// contradicts the exact sign. Then the filter in place: joint curvatures of
// splines far from the origin (where Tracked's 2^-40 bound cannot hold, so
// every fast answer comes from the double-word filter or the exact path) are
// bit for bit those of the exact-only path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "bezierize/analyze.hpp"
#include "numeric/double_word.hpp"
#include "numeric/fast_path.hpp"

namespace cmr {
namespace {

struct Pair {
  DoubleWord w;
  Rational x;
  std::string text;
};

// Leaves of the kinds blossoms meet: small integers, dyadic fractions, knots
// like 0.1 (not dyadic), large coordinates beside small differences, zero.
Pair leaf(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> kind(0, 5), small(-50, 50), exponent(-40, 40);
  std::uniform_real_distribution<double> unit(-1, 1);
  double v = 0;
  switch (kind(rng)) {
    case 0: v = small(rng); break;
    case 1: v = std::ldexp(small(rng), -exponent(rng) / 4); break;
    case 2: v = small(rng) * 0.1; break;
    case 3: v = std::ldexp(unit(rng), exponent(rng)); break;
    case 4: v = 1e7 + unit(rng); break;
    default: v = 0; break;
  }
  return {DoubleWord(v), Rational(v), std::to_string(v)};
}

// A random expression of depth <= depth; nullopt where it divides by an
// exact zero.
std::optional<Pair> expression(std::mt19937_64& rng, int depth) {
  if (depth == 0 || rng() % 4 == 0) return leaf(rng);
  const auto a = expression(rng, depth - 1), b = expression(rng, depth - 1);
  if (!a || !b) return std::nullopt;
  switch (rng() % 4) {
    case 0: return Pair{a->w + b->w, a->x + b->x, "(" + a->text + " + " + b->text + ")"};
    case 1: return Pair{a->w - b->w, a->x - b->x, "(" + a->text + " - " + b->text + ")"};
    case 2: return Pair{a->w * b->w, a->x * b->x, "(" + a->text + " * " + b->text + ")"};
    default:
      if (sgn(b->x) == 0) return std::nullopt;
      return Pair{a->w / b->w, Rational(a->x / b->x), "(" + a->text + " / " + b->text + ")"};
  }
}

TEST(DoubleWord, ExactValueLiesWithinTheBoundAndTruncationIsTheExactOne) {
  std::mt19937_64 rng(2023);
  int bounded = 0, truncated = 0, total = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const auto p = expression(rng, 1 + trial % 6);
    if (!p) continue;
    ++total;
    const DoubleWord& w = p->w;
    const int sign = certain_sign(w);
    if (sign != kSignUnknown) {
      ASSERT_EQ(sign, sgn(p->x)) << p->text;
    }
    if (!w.bounded()) continue;
    ++bounded;
    const Rational error = abs(p->x - Rational(w.hi) - Rational(w.lo));
    ASSERT_LE(error, Rational(w.e)) << p->text << ": value " << w.hi << " + " << w.lo << ", bound " << w.e;
    if (const std::optional<double> t = w.truncated()) {
      ++truncated;
      const double exact = p->x.get_d();  // GMP truncates toward zero
      ASSERT_EQ(std::memcmp(&*t, &exact, sizeof exact), 0) << p->text << ": " << *t << " vs " << exact;
    }
  }
  EXPECT_GT(bounded, total * 9 / 10);
  EXPECT_GT(truncated, bounded * 8 / 10) << "the filter should decide most truncations";
}

TEST(DoubleWord, TruncationNeedsTheWholeEnclosureInOneCell) {
  // 1 + 2^-60 with a bound of 2^-70: inside [1, next(1)): truncates to 1.
  const DoubleWord one_plus = DoubleWord(1.0) + DoubleWord(0x1p-60);
  ASSERT_TRUE(one_plus.truncated());
  EXPECT_EQ(*one_plus.truncated(), 1.0);
  // 1 - 2^-60: below 1, truncates to the double below 1.
  const DoubleWord one_minus = DoubleWord(1.0) - DoubleWord(0x1p-60);
  ASSERT_TRUE(one_minus.truncated());
  EXPECT_EQ(*one_minus.truncated(), std::nextafter(1.0, 0.0));
  // Negative values truncate toward zero.
  const DoubleWord minus = DoubleWord(-1.0) - DoubleWord(0x1p-60);
  ASSERT_TRUE(minus.truncated());
  EXPECT_EQ(*minus.truncated(), -1.0);
  // A value within its bound of a double: undecided.
  const DoubleWord third = DoubleWord(1.0) / DoubleWord(3.0);
  EXPECT_GT(third.e, 0.0);
  const DoubleWord back = third * DoubleWord(3.0);  // 1 within a few 2^-106
  EXPECT_FALSE(back.truncated());
  // No bound, and values out of the safe range: undecided.
  EXPECT_FALSE(DoubleWord(0x1p-950).truncated());
  EXPECT_FALSE((DoubleWord(1.0) / DoubleWord(0.0)).truncated());
  EXPECT_FALSE(DoubleWord::unknown().truncated());
  EXPECT_FALSE((DoubleWord(0x1p800) * DoubleWord(0x1p800)).bounded());
}

// A uniform cubic (or quadratic/quartic) B-spline on a random walk far from
// the origin, with knots that are not dyadic: Tracked's relative bound
// cannot hold there (the coordinates' rounding is 1e7 times the local
// differences), so the fast path's curvatures are the double-word filter's
// or the exact path's, and both must be the exact path's bits.
TEST(DoubleWord, JointCurvaturesFarFromTheOriginAreTheExactPathsBits) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> step(-1, 1), gap(0.3, 1.7);
  int ends = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const int d = 2 + trial % 3;
    const int m = d + 20;
    std::vector<Vec2> P;
    Vec2 p(1e7 * (trial % 2 ? 1 : -3), 4e6);
    for (int i = 0; i < m; ++i) {
      p += Vec2(1 + 0.3 * step(rng), step(rng));
      P.push_back(p);
    }
    std::vector<double> knots;
    double u = trial % 4 < 2 ? 0 : 1e5;  // far-off knots too
    for (int k = 0; k < m + d - 1; ++k) knots.push_back(u += (trial % 3 == 0 ? 0.1 : gap(rng)));
    const BSpline s = BSpline::make(d, knots, P, "far " + std::to_string(trial));
    for (const Segment& seg : s.segments())
      for (int side = 0; side < 2; ++side) {
        const double fast = certified_end_curvature(s, seg, side);
        double exact = 0;
        {
          const ExactOnlyScope scope;
          exact = certified_end_curvature(s, seg, side);
        }
        ++ends;
        ASSERT_EQ(std::memcmp(&fast, &exact, sizeof fast), 0)
            << s.name() << " segment " << seg.index << " side " << side << ": " << fast << " vs " << exact;
      }
  }
  EXPECT_GT(ends, 400);
}

}  // namespace
}  // namespace cmr
