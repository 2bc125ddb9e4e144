// The region setup's piece polynomials (region/region_pieces.hpp) against
// the method they replaced: lambda_bernstein / eta_bernstein (or their
// rational forms) on Poly3 Bezier points B0 + w (dx, dy), every subdivision
// piece down to piece_levels halved exactly in mpq (bernstein_halve), each
// monomial rounded by Rational::get_d, a non-zero coefficient whose monomials
// all round to zero marked with a NaN. The rounded xi and nu of every
// touched entry of prepare_region, and the entries' rounded Bezier points and
// influence weights with their error bounds, must equal the reference bit
// for bit, and their exact Bezier points and weights the blossoms' (which a
// Bezier window skips): on seeded B-splines and Beziers of degrees 2..15 (random knot
// gaps, so denominators are not powers of two), rational ones of degrees 2..6, at
// depths 0..3 and 12, and at coordinate scales whose coefficients underflow
// to subnormals or zero, or are near the top of the double range (the
// conversions' fallbacks).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "bezierize/extract.hpp"
#include "bezierize/lambda.hpp"
#include "numeric/poly3.hpp"
#include "bezierize/rational_lambda.hpp"
#include "region/region.hpp"
#include "region/region_pieces.hpp"
#include "region/region_setup.hpp"

namespace cmr {
namespace {

using namespace cmr::backend;

// ---- The replaced method (region.cpp before issue 23), kept as the reference ----

template <std::size_t K>
std::array<double, K> reference_rounded_poly(const Poly3& p) {
  std::array<double, K> r{};
  bool exact_zero = true, all_rounded_zero = true;
  for (std::size_t m = 0; m < K; ++m) {
    r[m] = p.c[m].get_d();
    exact_zero = exact_zero && sgn(p.c[m]) == 0;
    all_rounded_zero = all_rounded_zero && r[m] == 0;
  }
  if (all_rounded_zero && !exact_zero) r[0] = std::numeric_limits<double>::quiet_NaN();
  return r;
}

std::vector<Bernstein<Poly3>> reference_piece_polynomials(const Bernstein<Poly3>& root, int levels) {
  std::vector<Bernstein<Poly3>> pieces{root};
  const std::size_t n1 = root.size();
  const Poly3 half(Rational(1, 2));
  const auto mid = [&](const Poly3& a, const Poly3& b) { return half * (a + b); };
  for (std::size_t p = 0; pieces.size() < (std::size_t{2} << levels) - 1; ++p) {
    Bernstein<Poly3> left(n1), right(n1), work(n1);
    bernstein_halve(pieces[p].data(), n1, left.data(), right.data(), work.data(), mid);
    pieces.push_back(std::move(left));
    pieces.push_back(std::move(right));
  }
  return pieces;
}

struct Reference {
  std::vector<std::array<double, 10>> xi;
  std::vector<std::array<double, 3>> nu;
};

Reference reference_pieces(const RegionEntry& e, int levels) {
  std::vector<Point<Poly3>> P;
  std::vector<HPoint<Poly3>> H;
  for (std::size_t i = 0; i < e.base_exact.size(); ++i) {
    P.push_back({Poly3(e.base_exact[i].x) + Poly3(e.weight_exact[i]) * Poly3::x(),
                 Poly3(e.base_exact[i].y) + Poly3(e.weight_exact[i]) * Poly3::y()});
    if (!e.hw_exact.empty()) H.push_back({P.back().x, P.back().y, Poly3(e.hw_exact[i])});
  }
  const bool rational = !e.hw_exact.empty();
  Reference r;
  for (const Bernstein<Poly3>& piece : reference_piece_polynomials(
           rational ? rational_lambda_bernstein<Poly3>(H) : lambda_bernstein<Poly3>(P), levels))
    for (const Poly3& c : piece) r.xi.push_back(reference_rounded_poly<10>(c));
  for (const Bernstein<Poly3>& piece : reference_piece_polynomials(
           rational ? rational_d_bernstein<Poly3>(H) : eta_bernstein<Poly3>(P), levels))
    for (const Poly3& c : piece) r.nu.push_back(reference_rounded_poly<3>(c));
  return r;
}

// ---- Comparison ----

// Where two rounded piece tables differ first: "" when equal bit for bit.
template <std::size_t K>
std::string first_difference(const std::vector<std::array<double, K>>& got,
                             const std::vector<std::array<double, K>>& want, std::size_t n1) {
  if (got.size() != want.size())
    return "sizes " + std::to_string(got.size()) + " and " + std::to_string(want.size());
  for (std::size_t o = 0; o < got.size(); ++o)
    for (std::size_t m = 0; m < K; ++m)
      if (std::bit_cast<std::uint64_t>(got[o][m]) != std::bit_cast<std::uint64_t>(want[o][m])) {
        std::ostringstream s;
        s.precision(17);
        s << "piece " << o / n1 << ", coefficient " << o % n1 << ", monomial " << m << ": " << got[o][m]
          << " instead of " << want[o][m];
        return s.str();
      }
  return "";
}

bool same_bits(const Bounded& a, const Bounded& b) {
  return std::bit_cast<std::uint64_t>(a.v) == std::bit_cast<std::uint64_t>(b.v) &&
         std::bit_cast<std::uint64_t>(a.e) == std::bit_cast<std::uint64_t>(b.e);
}

Bounded reference_rounded(const Rational& q) {
  const double v = q.get_d();  // rounded as set_moved_points has always rounded: error at most u |v|
  return Bounded(v, Bounded::kRound * std::fabs(v) + Bounded::kTiny);
}

// What the reference values held: NaN markers, subnormals, infinities.
struct Kinds {
  int nan = 0, subnormal = 0, infinite = 0;
  template <std::size_t K>
  void count(const std::vector<std::array<double, K>>& table) {
    for (const auto& c : table)
      for (double v : c) {
        nan += std::isnan(v);
        subnormal += std::fpclassify(v) == FP_SUBNORMAL;
        infinite += std::isinf(v);
      }
  }
};

// Every touched entry of the setup of `spline` with `point` moved, at depth D,
// against the reference; `label` names the case in a failure. The setup's
// entries are those of the problem scaled by 2^-scale_exponent (exact Bezier
// points included); with `unscaled` they are prepared again at exponent 0
// (the data as given: what extreme scales then put into the conversions).
Kinds expect_reference(const BSpline& spline, int point, int depth, const std::string& label,
                       bool unscaled = false) {
  Kinds kinds;
  RegionRequest o;
  o.point = point;
  o.max_depth = depth;
  o.width = o.height = 4;
  RegionSetup s = prepare_region(spline, o);
  if (unscaled) {
    s.scale_exponent = 0;
    s.scale = 1;
    for (RegionEntry& e : s.entries) {
      const int part = e.part;
      e = prepare_entry(s, e.segment, e.classify);
      e.part = part;
    }
  }
  // The exact factor of the entries' points (a power of two, exact as a double).
  const Rational factor(std::ldexp(1.0, -s.scale_exponent));
  int touched = 0;
  const int d = spline.degree();
  for (const RegionEntry& e : s.entries) {
    const std::string where = label + ", D " + std::to_string(depth) + ", segment " + std::to_string(e.segment);
    // The exact Bezier points and influence weights are the blossoms' (a Bezier window skips them).
    const Segment& g = spline.segments()[e.segment];
    const SegmentWindow<Rational> window = segment_window<Rational>(spline, g);
    const int first = g.span - d + 1;
    std::vector<Rational> indicator(d + 1, Rational(0));
    if (point >= first && point <= first + d) indicator[point - first] = Rational(spline.weight(point));
    EXPECT_TRUE(e.weight_exact == bezier_points(window.knots, indicator, d, window.span, Rational(g.a), Rational(g.b)))
        << where << ": influence weights";
    if (spline.is_rational()) {
      const std::vector<HPoint<Rational>> H = segment_homogeneous_points<Rational>(spline, g);
      for (std::size_t i = 0; i < H.size(); ++i)
        EXPECT_TRUE(e.base_exact[i].x == factor * H[i].x && e.base_exact[i].y == factor * H[i].y &&
                    e.hw_exact[i] == H[i].z)
            << where << ": homogeneous Bezier point " << i;
    } else {
      const std::vector<Point<Rational>> B =
          bezier_points(window.knots, window.points, d, window.span, Rational(g.a), Rational(g.b));
      for (std::size_t i = 0; i < B.size(); ++i)
        EXPECT_TRUE(e.base_exact[i].x == factor * B[i].x && e.base_exact[i].y == factor * B[i].y)
            << where << ": Bezier point " << i;
    }
    for (std::size_t i = 0; i < e.base_exact.size(); ++i) {
      EXPECT_TRUE(same_bits(e.base[i].x, reference_rounded(e.base_exact[i].x))) << where << ", B0 x " << i;
      EXPECT_TRUE(same_bits(e.base[i].y, reference_rounded(e.base_exact[i].y))) << where << ", B0 y " << i;
      EXPECT_TRUE(same_bits(e.weight[i], reference_rounded(e.weight_exact[i]))) << where << ", w " << i;
    }
    if (!e.classify) continue;
    ++touched;
    const Reference r = reference_pieces(e, s.piece_levels);
    kinds.count(r.xi);
    kinds.count(r.nu);
    EXPECT_EQ(first_difference(e.xi, r.xi, static_cast<std::size_t>(e.n_xi)), "") << where << ": xi";
    EXPECT_EQ(first_difference(e.nu, r.nu, static_cast<std::size_t>(e.n_nu)), "") << where << ": nu";
  }
  EXPECT_GT(touched, 0) << label;
  return kinds;
}

double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

// A seeded B-spline of degree d with `spans` spans: random knot gaps of
// 0.5, 1, ..., 2.5 (blossoms divide by their sums: denominators 3, 5, 7 ...;
// gaps of random doubles make the reference's gcds take minutes), end knots
// of multiplicity d when clamped,
// random points in [-scale, scale)^2, and weights in [0.5, 2) when rational.
BSpline random_spline(std::mt19937_64& rng, int d, int spans, double scale, bool clamped, bool rational) {
  const int points = d + spans;
  std::vector<double> knots;
  double t = 0;
  for (int i = 0; i < points + d - 1; ++i) {
    const bool end = clamped && (i < d || i >= points);
    if (!knots.empty() && !end) t += 0.5 * static_cast<double>(1 + rng() % 5);
    knots.push_back(t);
  }
  std::vector<Vec2> P;
  std::vector<double> w;
  for (int i = 0; i < points; ++i) {
    P.push_back(Vec2(scale * (2 * unit(rng) - 1), scale * (2 * unit(rng) - 1)));
    if (rational) w.push_back(0.5 + 1.5 * unit(rng));
  }
  return BSpline::make(d, std::move(knots), std::move(P), "seeded", std::move(w));
}

TEST(RegionPieces, BeziersOfDegrees2To15EqualTheExactHalving) {
  std::mt19937_64 rng(2315);
  for (int d = 2; d <= 15; ++d) {
    std::vector<Vec2> P;
    for (int i = 0; i <= d; ++i) P.push_back(Vec2(2 * unit(rng) - 1, 2 * unit(rng) - 1));
    const BSpline bezier = BSpline::bezier(P, "seeded");
    for (const int depth : {0, 1, 2, 12})
      expect_reference(bezier, d / 2, depth, "Bezier of degree " + std::to_string(d));
  }
}

TEST(RegionPieces, BSplinesOfDegrees2To15EqualTheExactHalving) {
  std::mt19937_64 rng(23);
  for (int d = 2; d <= 15; ++d)
    for (const bool clamped : {false, true}) {
      const BSpline s = random_spline(rng, d, 2, 1.0, clamped, false);
      expect_reference(s, s.point_count() / 2, 12,
                       "B-spline of degree " + std::to_string(d) + (clamped ? ", clamped" : ", floating"));
    }
}

TEST(RegionPieces, RationalSplinesEqualTheExactHalving) {
  std::mt19937_64 rng(77);
  for (int d = 2; d <= 6; ++d) {
    const BSpline s = random_spline(rng, d, 2, 1.0, true, true);
    expect_reference(s, s.point_count() / 2, 3, "rational B-spline of degree " + std::to_string(d));
    std::vector<Vec2> P;
    std::vector<double> w;
    for (int i = 0; i <= d; ++i) {
      P.push_back(Vec2(2 * unit(rng) - 1, 2 * unit(rng) - 1));
      w.push_back(0.5 + 1.5 * unit(rng));
    }
    expect_reference(BSpline::bezier(P, "seeded", w), d / 2, 3, "rational Bezier of degree " + std::to_string(d));
  }
}

TEST(RegionPieces, ExtremeScalesEqualTheExactHalving) {
  // lambda scales as the 4th power of the coordinates: 1e-80 puts its
  // constant terms below the subnormal range (the NaN marker), 1e-77 among
  // subnormals, 1e70 near the top of the double range, 1e80 past it. So the
  // data as given (unscaled); the setup itself scales such data near 1
  // (RegionSetup::scale_exponent), checked too.
  std::mt19937_64 rng(5);
  Kinds kinds;
  const auto add = [&](const Kinds& k) {
    kinds.nan += k.nan;
    kinds.subnormal += k.subnormal;
    kinds.infinite += k.infinite;
  };
  for (const double scale : {1e-80, 1e-77, 1e-30, 1e30, 1e70, 1e80})
    for (const int d : {3, 7}) {
      std::ostringstream label;
      label << "degree " << d << " at scale " << scale;
      const BSpline s = random_spline(rng, d, 2, scale, false, false);
      add(expect_reference(s, s.point_count() / 2, 3, label.str(), true));
      expect_reference(s, s.point_count() / 2, 3, "scaled, " + label.str());
      std::vector<Vec2> P;
      for (int i = 0; i <= d; ++i) P.push_back(Vec2(scale * (2 * unit(rng) - 1), scale * (2 * unit(rng) - 1)));
      add(expect_reference(BSpline::bezier(P, "seeded"), d / 2, 3, "Bezier, " + label.str(), true));
      expect_reference(BSpline::bezier(P, "seeded"), d / 2, 3, "scaled Bezier, " + label.str());
    }
  // The cases reach what they are here for (the NaN marker: RoundedPiecesOfArbitraryRationals).
  EXPECT_GT(kinds.subnormal, 0) << "no subnormal coefficient";
  EXPECT_GT(kinds.infinite, 0) << "no coefficient overflowed";
}

TEST(RegionPieces, RoundedPiecesOfArbitraryRationals) {
  // rounded_pieces alone (the rational splines' path) on seeded coefficients
  // m 2^e / odd: magnitudes from 2^-1250 (every monomial of a coefficient
  // rounds to zero: the NaN marker) through subnormals to 2^1100
  // (infinities), odd denominators up to 2^40, some monomials exactly zero,
  // levels 0..3.
  std::mt19937_64 rng(99);
  Kinds kinds;
  for (int round = 0; round < 60; ++round) {
    const int n1 = 2 + static_cast<int>(rng() % 12), levels = static_cast<int>(rng() % 4);
    constexpr long kBands[] = {-1250, -1110, -1080, -1060, -1040, -500, 0, 500, 1000, 1020};  // tiny .. huge
    const long scale = kBands[round % 10] + static_cast<long>(rng() % 20);
    const bool affine = rng() % 2 == 0;
    Bernstein<Poly3> root(static_cast<std::size_t>(n1));
    for (Poly3& c : root)
      for (int m = 0; m < (affine ? 3 : kPoly3Terms); ++m) {
        if (rng() % 5 == 0) continue;  // an exact zero
        mpz_class num(static_cast<unsigned long>(rng() >> 1)), den(static_cast<unsigned long>((rng() >> 24) | 1));
        if (rng() % 2) num = -num;
        Rational v(num, den);
        v.canonicalize();
        const long e = scale + static_cast<long>(rng() % 40);
        if (e >= 0) mpq_mul_2exp(v.get_mpq_t(), v.get_mpq_t(), static_cast<mp_bitcnt_t>(e));
        else mpq_div_2exp(v.get_mpq_t(), v.get_mpq_t(), static_cast<mp_bitcnt_t>(-e));
        c.c[m] = v;
      }
    const std::string where = "round " + std::to_string(round) + " (" + std::to_string(n1) + " coefficients, 2^" +
                              std::to_string(scale) + ", levels " + std::to_string(levels) + ")";
    std::vector<std::array<double, 10>> xi;
    std::vector<std::array<double, 3>> nu;
    for (const Bernstein<Poly3>& piece : reference_piece_polynomials(root, levels))
      for (const Poly3& c : piece) {
        xi.push_back(reference_rounded_poly<10>(c));
        if (affine) nu.push_back(reference_rounded_poly<3>(c));
      }
    kinds.count(xi);
    EXPECT_EQ(first_difference(rounded_pieces<10>(root, levels), xi, static_cast<std::size_t>(n1)), "") << where;
    if (affine) {
      EXPECT_EQ(first_difference(rounded_pieces<3>(root, levels), nu, static_cast<std::size_t>(n1)), "") << where;
    }
  }
  EXPECT_GT(kinds.nan, 0) << "no coefficient underflowed to the NaN marker";
  EXPECT_GT(kinds.subnormal, 0) << "no subnormal coefficient";
  EXPECT_GT(kinds.infinite, 0) << "no coefficient overflowed";
}

TEST(RegionPieces, StructuralZerosStayExact) {
  // Collinear points: eta is zero where dx, dy vanish, lambda has exactly zero monomials.
  std::vector<Vec2> P;
  for (int i = 0; i <= 5; ++i) P.push_back(Vec2(i * 0.75, i * 0.25));
  expect_reference(BSpline::bezier(P, "line"), 2, 3, "collinear Bezier");
  // Every piece of a polynomial whose monomials are exactly zero rounds to exact zeros.
  Bernstein<Poly3> zero(6);
  for (const auto& c : rounded_pieces<10>(zero, 2))
    for (double v : c) EXPECT_EQ(std::bit_cast<std::uint64_t>(v), std::uint64_t{0});
}

}  // namespace
}  // namespace cmr
