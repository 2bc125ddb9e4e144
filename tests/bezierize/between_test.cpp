// The certificate between two masters (bezierize/between.hpp): its tensor
// coefficients against the independent exact script, its verdicts against the
// exact single-piece classifier (Algorithms 1 and 2 in rationals) at rational
// locations between the masters.
#include "bezierize/between.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "bezierize/algorithms.hpp"
#include "bezierize/classify.hpp"
#include "bezierize/lambda.hpp"
#include "numeric/scalar.hpp"
#include "spline/errors.hpp"
#include "tests/bezierize/between_reference.hpp"

namespace cmr {
namespace {

std::vector<Vec2> points(const std::vector<std::pair<double, double>>& p) {
  std::vector<Vec2> out;
  for (const auto& [x, y] : p) out.push_back({x, y});
  return out;
}

const reference::BetweenReference& pair_named(const std::string& name) {
  for (const auto& r : reference::between_references())
    if (name == r.name) return r;
  throw std::runtime_error("no reference pair " + name);
}

/// The exact instance (1 - s) A + s B at a rational s.
std::vector<Point<Rational>> instance(const std::vector<Vec2>& A, const std::vector<Vec2>& B, const Rational& s) {
  std::vector<Point<Rational>> P;
  for (std::size_t i = 0; i < A.size(); ++i) {
    const Rational x = (1 - s) * A[i].x + s * B[i].x, y = (1 - s) * A[i].y + s * B[i].y;
    P.push_back({x, y});
  }
  return P;
}

/// The exact single-piece classifier (Algorithm 1 in rationals) at s.
Curvature curvature_at(const std::vector<Vec2>& A, const std::vector<Vec2>& B, const Rational& s,
                       int depth = kDefaultDepth) {
  return algorithm1(lambda_bernstein<Rational>(instance(A, B, s)), depth)->curvature;
}
Inflection inflection_at(const std::vector<Vec2>& A, const std::vector<Vec2>& B, const Rational& s,
                         int depth = kDefaultDepth) {
  return algorithm2(eta_bernstein<Rational>(instance(A, B, s)), depth)->inflection;
}
bool monotone(Curvature c) {
  return c == Curvature::increasing || c == Curvature::decreasing || c == Curvature::constant;
}

Rational random_rational(std::mt19937& rng, double lo, double hi) {
  // A non-dyadic rational in [lo, hi): lo + (hi - lo) k / q.
  const long q = std::uniform_int_distribution<long>(3, 1000003)(rng) | 1;
  const long k = std::uniform_int_distribution<long>(0, q - 1)(rng);
  return Rational(lo) + (Rational(hi) - Rational(lo)) * Rational(k) / Rational(q);
}

TEST(Between, TensorMatchesTheExactScript) {
  for (const auto& ref : reference::between_references()) {
    SCOPED_TRACE(ref.name);
    const std::vector<Vec2> A = points(ref.a), B = points(ref.b);
    const int n = static_cast<int>(A.size()) - 1;
    const BetweenTensor lam = lambda_between_tensor(A, B), eta = eta_between_tensor(A, B);
    EXPECT_EQ(lam.deg_t, 4 * n - 7);
    EXPECT_EQ(lam.deg_s, 4);
    EXPECT_EQ(eta.deg_t, 2 * n - 4);
    EXPECT_EQ(eta.deg_s, 2);
    EXPECT_EQ(lam.exact, ref.lambda);
    EXPECT_EQ(eta.exact, ref.eta);
    // The bounded coefficients enclose the exact ones.
    for (const BetweenTensor* t : {&lam, &eta})
      for (std::size_t k = 0; k < t->exact.size(); ++k) {
        const Rational exact(t->exact[k]);
        const Rational gap = abs(exact - Rational(t->value[k]));
        EXPECT_LE(gap, Rational(t->error[k])) << k;
      }
  }
}

TEST(Between, SimilarInstancesAreMonotoneThroughout) {
  // (a) B = 2A: every instance (1 + s) A is similar to A; lambda scales by
  // (1 + s)^4 and keeps its sign.
  const auto& ref = pair_named("cubic_similar");
  const std::vector<Vec2> A = points(ref.a), B = points(ref.b);
  for (std::size_t i = 0; i < A.size(); ++i) ASSERT_EQ(B[i], 2.0 * A[i]);
  ASSERT_EQ(classify_bezier(A).monotonicity.curvature, Curvature::increasing);
  const BetweenVerdict v = monotone_between(A, B);
  EXPECT_EQ(v.kind, BetweenVerdict::Kind::holds_throughout) << to_string(v.kind);
  EXPECT_EQ(v.direction, 1);
  EXPECT_EQ(v.s_lower, 1.0);
  EXPECT_EQ(v.s_first_fail, -1.0);
  EXPECT_GT(v.cells_float, 0);
  const BetweenVerdict e = inflection_free_between(A, B);
  EXPECT_EQ(e.kind, BetweenVerdict::Kind::holds_throughout);
  EXPECT_EQ(e.direction, 1);
}

TEST(Between, BumpBetweenIncreasingMastersFailsNearTheFirstFailure) {
  // (b) curvature increasing at both masters, an interior extremum at the
  // halfway instance (exactly: Algorithm 1 in rationals at s = 1/2).
  const auto& ref = pair_named("cubic_bump");
  const std::vector<Vec2> A = points(ref.a), B = points(ref.b);
  ASSERT_EQ(classify_bezier(A).monotonicity.curvature, Curvature::increasing);
  ASSERT_EQ(classify_bezier(B).monotonicity.curvature, Curvature::increasing);
  ASSERT_EQ(curvature_at(A, B, 0), Curvature::increasing);
  ASSERT_EQ(curvature_at(A, B, 1), Curvature::increasing);
  ASSERT_EQ(curvature_at(A, B, Rational(1, 2)), Curvature::non_monotone);

  BetweenOptions o;
  const BetweenVerdict v = monotone_between(A, B, o);
  ASSERT_EQ(v.kind, BetweenVerdict::Kind::fails) << to_string(v.kind);
  std::printf("bump: s in [%.9f, %.9f] (first failure), t = %.9f, cells %lld float, %lld exact, %d witness runs\n",
              v.s_lower, v.s_first_fail, v.t_witness, static_cast<long long>(v.cells_float),
              static_cast<long long>(v.cells_exact), v.witnesses_tried);
  // The witness fails exactly; everything below s_lower is monotone; the
  // first failure is bracketed to 2^-s_depth (here the first interval not
  // certified holds the witness).
  EXPECT_EQ(curvature_at(A, B, Rational(v.s_first_fail)), Curvature::non_monotone);
  EXPECT_GT(v.s_lower, 0.0);
  EXPECT_LE(v.s_lower, v.s_first_fail);
  EXPECT_LT(v.s_first_fail, 0.5);
  EXPECT_LE(v.s_first_fail - v.s_lower, std::ldexp(1.0, -o.s_depth));
  std::mt19937 rng(37);
  for (int k = 0; k < 30; ++k) EXPECT_TRUE(monotone(curvature_at(A, B, random_rational(rng, 0, v.s_lower))));
  // Here the extremum enters through the end t = 1: the first failure is
  // the first root of lambda(1, s), isolated exactly by another route
  // (roots.hpp on the tensor's last row) and bracketed by the verdict.
  const NodeBetween node = node_lambda_between(A, B, A, B);
  EXPECT_NEAR(v.t_witness, 1.0, 1e-3);
  EXPECT_LE(v.s_lower, node.left_zero_s + 1e-12);
  EXPECT_GE(v.s_first_fail, node.left_zero_s - 1e-12);
  // t_witness is within 1e-12 of a sign change of lambda(., s_first_fail).
  ASSERT_GE(v.t_witness, 0.0);
  ASSERT_LE(v.t_witness, 1.0);
  const Bernstein<Rational> lam = lambda_bernstein<Rational>(instance(A, B, Rational(v.s_first_fail)));
  const Rational eps(1e-11);
  const Rational before(Rational(v.t_witness) - eps), after(Rational(v.t_witness) + eps);
  EXPECT_NE(sgn(bernstein_eval(lam, before)), sgn(bernstein_eval(lam, after)));
}

TEST(Between, RandomPairsAgreeWithTheExactClassifier) {
  // (c) Seeded pairs whose masters are both monotone in one direction (so
  // the question is what happens between), and some on one line (lambda
  // == 0: every coefficient an exact 0, decided by the exact path).
  std::mt19937 rng(20261202);
  std::uniform_int_distribution<int> coord(-6, 6), nudge(-5, 5), degree(2, 4);
  int holds = 0, fails = 0, undecided = 0, pairs = 0;
  std::int64_t cells_float = 0, cells_exact = 0;
  while (pairs < 60) {
    const int n = degree(rng);
    std::vector<Vec2> A, B;
    const bool line = pairs % 10 == 9;
    for (int i = 0; i <= n; ++i) {
      if (line) {
        A.push_back({i + 0.5 * coord(rng), 0});
        B.push_back({i + 0.5 * coord(rng), 0});
        A.back().y = 2 * A.back().x;
        B.back().y = 2 * B.back().x;
        continue;
      }
      A.push_back({4.0 * i + coord(rng), 2.0 * i * i / n + coord(rng)});
      B.push_back({A.back().x + nudge(rng), A.back().y + nudge(rng)});
    }
    const Curvature ca = classify_bezier(A).monotonicity.curvature, cb = classify_bezier(B).monotonicity.curvature;
    if (!monotone(ca) || ca != cb) continue;
    ++pairs;
    SCOPED_TRACE(pairs);
    const BetweenVerdict v = monotone_between(A, B);
    cells_float += v.cells_float;
    cells_exact += v.cells_exact;
    if (v.kind == BetweenVerdict::Kind::holds_throughout) {
      ++holds;
      for (int k = 0; k < 50; ++k) {
        const Rational s = random_rational(rng, 0, 1);
        const Curvature c = curvature_at(A, B, s);
        EXPECT_TRUE(monotone(c)) << s.get_str() << " " << to_string(c);
        if (v.direction == 1) {
          EXPECT_NE(c, Curvature::decreasing);
        }
        if (v.direction == -1) {
          EXPECT_NE(c, Curvature::increasing);
        }
      }
    } else if (v.kind == BetweenVerdict::Kind::fails) {
      ++fails;
      EXPECT_EQ(curvature_at(A, B, Rational(v.s_first_fail)), Curvature::non_monotone);
      EXPECT_LE(v.s_lower, v.s_first_fail);
      for (int k = 0; k < 10 && v.s_lower > 0; ++k)
        EXPECT_TRUE(monotone(curvature_at(A, B, random_rational(rng, 0, v.s_lower))));
    } else {
      ++undecided;
      std::printf("undecided (s_lower %.9f, line %d):", v.s_lower, line ? 1 : 0);
      for (std::size_t i = 0; i < A.size(); ++i) std::printf(" (%g,%g)-(%g,%g)", A[i].x, A[i].y, B[i].x, B[i].y);
      std::printf("\n");
    }
  }
  const double share = static_cast<double>(cells_exact) / static_cast<double>(cells_float + cells_exact);
  std::printf("random pairs: %d monotone throughout, %d fail, %d undecided; cells: %lld float, %lld exact (%.2f%% exact)\n",
              holds, fails, undecided, static_cast<long long>(cells_float), static_cast<long long>(cells_exact),
              100 * share);
  EXPECT_GE(holds, 5);
  EXPECT_GE(fails, 3);
  EXPECT_GT(cells_exact, 0);  // the straight pairs
}

TEST(Between, InflectionBetweenMastersIsBracketedExactly) {
  // A bends right, B left. With P1 = (3, 4 - 8s), P2 = (6, 4 - 10s) the legs
  // are e1 = (3, 4 - 8s), e2 = (3, -2s), e3 = (3, 10s - 4), and eta's
  // coefficients are multiples of det(e1, e2) = 18s - 12, det(e1, e3) =
  // 54s - 24 and det(e2, e3) = 36s - 12 (positive factors): all < 0 for
  // s < 1/3, and eta(1) = 0 at s = 1/3. So the first inflection is exactly at
  // s = 1/3 (Algorithm 2, rule 1).
  const std::vector<Vec2> A{{0, 0}, {3, 4}, {6, 4}, {9, 0}}, B{{0, 0}, {3, -4}, {6, -6}, {9, 0}};
  ASSERT_EQ(inflection_at(A, B, 0), Inflection::none);
  ASSERT_EQ(inflection_at(A, B, 1), Inflection::none);
  ASSERT_EQ(inflection_at(A, B, Rational(1, 3)), Inflection::present);
  BetweenOptions o;
  const BetweenVerdict v = inflection_free_between(A, B, o);
  ASSERT_EQ(v.kind, BetweenVerdict::Kind::fails) << to_string(v.kind);
  EXPECT_EQ(inflection_at(A, B, Rational(v.s_first_fail)), Inflection::present);
  EXPECT_LE(Rational(v.s_lower), Rational(1, 3));
  EXPECT_GE(Rational(v.s_first_fail), Rational(1, 3));
  EXPECT_LE(v.s_first_fail - v.s_lower, std::ldexp(1.0, -o.s_depth));
  EXPECT_NEAR(v.t_witness, 1.0, 1e-4);  // eta(1) > 0 just past 1/3: the root is near t = 1
  // Masters bent the same way, B = 2A: no inflection anywhere.
  std::vector<Vec2> A2 = A;
  for (Vec2& p : A2) p *= 2.0;
  const BetweenVerdict same = inflection_free_between(A, A2, o);
  EXPECT_EQ(same.kind, BetweenVerdict::Kind::holds_throughout);
  EXPECT_EQ(same.direction, -1);
}

TEST(Between, NodeSignsForEveryLocation) {
  // The similar pair keeps lambda's sign at both ends for every s.
  const auto& sim = pair_named("cubic_similar");
  const std::vector<Vec2> A = points(sim.a), B = points(sim.b);
  const NodeBetween kept = node_lambda_between(A, B, A, B);
  EXPECT_TRUE(kept.pattern_kept());
  EXPECT_EQ(kept.left_sign, sgn(lambda_bernstein<Rational>(instance(A, B, 0)).back()));
  EXPECT_EQ(kept.right_sign, sgn(lambda_bernstein<Rational>(instance(A, B, 0)).front()));
  EXPECT_EQ(kept.left_zero_s, -1.0);
  // The bump pair: lambda at t = 1 changes sign between the masters (the
  // instance's extremum passes through the node): the zero is a sign change
  // of the exact lambda(1, s).
  const auto& bump = pair_named("cubic_bump");
  const std::vector<Vec2> C = points(bump.a), D = points(bump.b);
  const NodeBetween moved = node_lambda_between(C, D, C, D);
  EXPECT_FALSE(moved.pattern_kept());
  ASSERT_GT(moved.left_zero_s, 0.0);
  ASSERT_LT(moved.left_zero_s, 1.0);
  const Rational eps(1e-9), z(moved.left_zero_s);
  EXPECT_NE(sgn(lambda_bernstein<Rational>(instance(C, D, z - eps)).back()),
            sgn(lambda_bernstein<Rational>(instance(C, D, z + eps)).back()));
}

TEST(Between, AStraightInstanceBetweenIsFactoredOut) {
  // A parabola bent one way at A and the other at B: with hodograph points
  // q0 = (1, 1/2 - 3s/4), q1 = (3, 3s/2 - 1/2) (times 4 here) the instance is
  // straight where det(q0, q1) = 15s/4 - 2 = 0, s = 8/15 (lambda == 0 for
  // every t): no s-interval around 8/15 can be certified on lambda's
  // coefficients, but lambda = h(s) mu(t, s) with h(8/15) = 0 and mu is
  // certified. q0.(q1 - q0) and q1.(q1 - q0) stay > 0 (the speed grows, the
  // parabola's vertex stays outside): every instance is monotone, the
  // direction flips at 8/15.
  const std::vector<Vec2> A{{0, 0}, {4, 2}, {16, 0}}, B{{0, 0}, {4, -1}, {16, 3}};
  ASSERT_EQ(curvature_at(A, B, Rational(8, 15)), Curvature::constant);
  const BetweenVerdict v = monotone_between(A, B);
  EXPECT_EQ(v.kind, BetweenVerdict::Kind::holds_throughout) << to_string(v.kind);
  EXPECT_EQ(v.direction, 0);
  EXPECT_NE(curvature_at(A, B, 0), curvature_at(A, B, 1));
  std::mt19937 rng(3);
  for (int k = 0; k < 50; ++k) EXPECT_TRUE(monotone(curvature_at(A, B, random_rational(rng, 0, 1))));
  // Inflections: the straight instance at s = 8/15 alone has eta == 0
  // (Algorithm 2: present); the instances on either side bend one way each.
  // No dyadic s fails, so there is no witness: undecided, with everything
  // below 8/15 certified to 2^-s_depth.
  BetweenOptions o;
  const BetweenVerdict e = inflection_free_between(A, B, o);
  EXPECT_EQ(e.kind, BetweenVerdict::Kind::undecided) << to_string(e.kind);
  EXPECT_LE(Rational(e.s_lower), Rational(8, 15));
  EXPECT_GE(Rational(e.s_lower) + Rational(std::ldexp(1.0, -o.s_depth)), Rational(8, 15));
}

TEST(Between, BadInputIsOneLineInputError) {
  const std::vector<Vec2> A{{0, 0}, {1, 1}, {2, 0}, {3, 1}};
  const auto one_line = [](auto f) {
    try {
      f();
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos);
      EXPECT_NE(m.find("between masters"), std::string::npos);
      return true;
    }
    return false;
  };
  EXPECT_TRUE(one_line([&] { monotone_between(A, {{0, 0}, {1, 1}, {2, 0}}); }));
  EXPECT_TRUE(one_line([&] { monotone_between({{0, 0}, {1, 1}}, {{0, 0}, {1, 2}}); }));
  EXPECT_TRUE(one_line([&] { monotone_between(A, {{0, 0}, {1, 1}, {2, std::nan("")}, {3, 1}}); }));
  BetweenOptions o;
  o.s_depth = 60;
  EXPECT_TRUE(one_line([&] { monotone_between(A, A, o); }));
  EXPECT_TRUE(one_line([&] { node_lambda_between(A, A, A, {{0, 0}}); }));
}

}  // namespace
}  // namespace cmr
