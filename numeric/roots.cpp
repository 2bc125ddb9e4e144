#include "numeric/roots.hpp"

#include <tuple>

#include "numeric/root_signs.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>

#include "spline/errors.hpp"

namespace cmr {

namespace {

// Halving deeper than this without isolating every root means a multiple root
// (or two simple roots closer than 2^-48, for which the square-free route is
// merely slower): switch to Yun's decomposition.
constexpr int kIsolationDepth = 48;

// k / 2^level: the dyadic points and pieces that halving [0, 1] produces.
struct Dyadic {
  mpz_class k;
  int level = 0;
};

Rational to_rational(const Dyadic& x) {
  Rational r(x.k);
  mpq_div_2exp(r.get_mpq_t(), r.get_mpq_t(), static_cast<mp_bitcnt_t>(x.level));
  return r;
}

Dyadic child(const Dyadic& x, int which) { return {2 * x.k + which, x.level + 1}; }

// A root found by isolation: exactly at `at`, or strictly inside the piece
// (at, at + 2^-level) where its square-free polynomial has sign `sign_lo`
// just right of the left end.
struct Found {
  Dyadic at;
  bool exact = false;
  int sign_lo = 0;
  int multiplicity = 1;
  int poly = 0;  // which square-free polynomial it is a simple root of
};

int sign_variations(const Bernstein<Rational>& c) {
  int v = 0, last = 0;
  for (const Rational& x : c) {
    const int s = sgn(x);  // exact: zero coefficients are skipped, as Descartes' rule requires
    if (s == 0) continue;
    if (last != 0 && s != last) ++v;
    last = s;
  }
  return v;
}

// Signs of one polynomial at dyadic points: in double with a certified error
// bound first, exactly when the bound straddles zero.
class SignOracle {
 public:
  explicit SignOracle(Bernstein<Rational> q) : q_(std::move(q)) {
    for (const Rational& c : q_) {
      const double v = c.get_d();  // truncated: off by less than one unit in the last place
      bounded_.push_back(Bounded(v, Bounded::kRound * std::fabs(v) + Bounded::kTiny));
    }
  }

  int sign_at(const Dyadic& x) const {
    // x is a double exactly when its numerator has at most 53 bits (and it is
    // not subnormal); then only the evaluation rounds, and Bounded tracks it.
    if (mpz_sizeinbase(x.k.get_mpz_t(), 2) <= 53 && x.level < 1000) {
      const double t = std::ldexp(x.k.get_d(), -x.level);
      const int s = certain_sign(bernstein_eval(bounded_, Bounded(t)));
      if (s != kSignUnknown) return s;
    }
    return sgn(bernstein_eval(q_, to_rational(x)));
  }

  const Bernstein<Rational>& poly() const { return q_; }

 private:
  Bernstein<Rational> q_;
  Bernstein<Bounded> bounded_;
};

// Descartes-rule isolation of the roots of q in [0, 1]. With depth_limit >= 0,
// gives up (returns false) when a piece that still has two or more sign
// variations would have to be halved past that level.
bool isolate(const Bernstein<Rational>& q, int poly, int depth_limit, std::vector<Found>& out) {
  if (sgn(q.front()) == 0) out.push_back({{0, 0}, true, 0, 1, poly});
  if (sgn(q.back()) == 0) out.push_back({{1, 0}, true, 0, 1, poly});
  struct Piece {
    Dyadic at;
    Bernstein<Rational> c;
  };
  std::vector<Piece> stack;
  stack.push_back({{0, 0}, q});
  const std::size_t n1 = q.size();
  Bernstein<Rational> left(n1), right(n1), work(n1);
  while (!stack.empty()) {
    Piece piece = std::move(stack.back());
    stack.pop_back();
    const int v = sign_variations(piece.c);
    if (v == 0) continue;
    if (v == 1) {
      const auto first = std::find_if(piece.c.begin(), piece.c.end(), [](const Rational& x) { return sgn(x) != 0; });
      out.push_back({piece.at, false, sgn(*first), 1, poly});
      continue;
    }
    if (depth_limit >= 0 && piece.at.level >= depth_limit) return false;
    bernstein_halve(piece.c.data(), n1, left.data(), right.data(), work.data());
    if (sgn(left.back()) == 0) out.push_back({child(piece.at, 1), true, 0, 1, poly});
    stack.push_back({child(piece.at, 1), right});
    stack.push_back({child(piece.at, 0), left});
  }
  return true;
}

// One bisection step on a non-exact root.
void bisect(Found& f, const SignOracle& oracle) {
  const Dyadic mid = child(f.at, 1);
  const int s = oracle.sign_at(mid);
  if (s == 0) {
    f.at = mid;
    f.exact = true;
  } else {
    f.at = child(f.at, s == f.sign_lo ? 1 : 0);
  }
}

Rational lower(const Found& f) { return to_rational(f.at); }
Rational upper(const Found& f) { return f.exact ? to_rational(f.at) : to_rational({f.at.k + 1, f.at.level}); }

// Order of the first derivative of p that does not vanish at r (p(r) == 0).
int multiplicity_at(const Bernstein<Rational>& p, const Rational& r) {
  int m = 1;
  for (Bernstein<Rational> d = bernstein_derivative(p); sgn(bernstein_eval(d, r)) == 0; d = bernstein_derivative(d))
    ++m;
  return m;
}

// ---- Polynomials in the power basis over Q, for Yun's algorithm only. ----

using Poly = std::vector<Rational>;  // a_0..a_n, no leading zero; empty is the zero polynomial

void trim(Poly& a) {
  while (!a.empty() && sgn(a.back()) == 0) a.pop_back();
}

Poly derivative(const Poly& a) {
  Poly d;
  for (std::size_t i = 1; i < a.size(); ++i) d.push_back(Rational(static_cast<long>(i)) * a[i]);
  trim(d);
  return d;
}

Poly minus(Poly a, const Poly& b) {
  if (a.size() < b.size()) a.resize(b.size());
  for (std::size_t i = 0; i < b.size(); ++i) a[i] -= b[i];
  trim(a);
  return a;
}

// a = q b + r with deg r < deg b; b non-zero.
void divide(Poly a, const Poly& b, Poly* quotient, Poly* remainder) {
  CMR_CHECK(!b.empty());
  Poly q(a.size() >= b.size() ? a.size() - b.size() + 1 : 0);
  while (a.size() >= b.size()) {
    const std::size_t shift = a.size() - b.size();
    const Rational f = a.back() / b.back();
    q[shift] = f;
    for (std::size_t i = 0; i < b.size(); ++i) a[shift + i] -= f * b[i];
    a.pop_back();  // the leading term cancels exactly
    trim(a);
  }
  if (quotient) *quotient = std::move(q);
  if (remainder) *remainder = std::move(a);
}

Poly exact_quotient(const Poly& a, const Poly& b) {
  Poly q, r;
  divide(a, b, &q, &r);
  CMR_CHECK(r.empty());
  return q;
}

Poly monic(Poly a) {
  if (a.empty()) return a;
  const Rational lead = a.back();
  for (Rational& x : a) x /= lead;
  return a;
}

// Monic greatest common divisor (Euclid; monic steps keep the rationals small).
Poly gcd(Poly a, Poly b) {
  while (!b.empty()) {
    Poly r;
    divide(a, b, nullptr, &r);
    a = std::move(b);
    b = monic(std::move(r));
  }
  return monic(std::move(a));
}

// a_j = C(n,j) sum_{i<=j} (-1)^{j-i} C(j,i) c_i.
Poly power_from_bernstein(const Bernstein<Rational>& c) {
  const int n = static_cast<int>(c.size()) - 1;
  Poly a(n + 1);
  for (int j = 0; j <= n; ++j) {
    Rational s = 0;
    for (int i = 0; i <= j; ++i) {
      const Rational term = Rational(to_mpz(binomial(j, i))) * c[i];
      if ((j - i) % 2 == 0)
        s += term;
      else
        s -= term;
    }
    a[j] = Rational(to_mpz(binomial(n, j))) * s;
  }
  trim(a);
  return a;
}

// b_i = sum_{j<=i} C(i,j) / C(n,j) a_j, at degree n = deg a.
Bernstein<Rational> bernstein_from_power(const Poly& a) {
  const int n = static_cast<int>(a.size()) - 1;
  Bernstein<Rational> b(n + 1, Rational(0));
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= i; ++j) b[i] += Scalar<Rational>::ratio(binomial(i, j), binomial(n, j)) * a[j];
  return b;
}

// Yun's algorithm: f = c f_1 f_2^2 ... f_k^k with f_i square-free and pairwise
// coprime; returns f_1..f_k (some may be constants).
std::vector<Poly> square_free_factors(const Poly& f) {
  const Poly fp = derivative(f);
  const Poly a0 = gcd(f, fp);
  Poly b = exact_quotient(f, a0);
  Poly d = minus(exact_quotient(fp, a0), derivative(b));
  std::vector<Poly> factors;
  while (b.size() > 1) {
    const Poly a = gcd(b, d);
    factors.push_back(a);
    b = exact_quotient(b, a);
    d = minus(exact_quotient(d, a), derivative(b));
  }
  return factors;
}

// Roots of distinct square-free factors may have overlapping enclosures;
// bisect the wider of two overlapping ones until the order is certain.
void separate(std::vector<Found>& roots, const std::vector<SignOracle>& oracles) {
  for (;;) {
    std::sort(roots.begin(), roots.end(), [](const Found& a, const Found& b) { return lower(a) < lower(b); });
    bool overlap = false;
    for (std::size_t i = 0; i + 1 < roots.size() && !overlap; ++i) {
      Found& a = roots[i];
      Found& b = roots[i + 1];
      if (upper(a) <= lower(b)) continue;
      overlap = true;
      // Two different roots: at least one enclosure is not a point.
      Found& wider = a.exact ? b : (b.exact ? a : (a.at.level <= b.at.level ? a : b));
      bisect(wider, oracles[wider.poly]);
    }
    if (!overlap) return;
  }
}

}  // namespace

bool is_zero(const Bernstein<Rational>& p) {
  return std::all_of(p.begin(), p.end(), [](const Rational& c) { return sgn(c) == 0; });
}

int sign_at_start(const Bernstein<Rational>& p) {
  for (const Rational& c : p)
    if (sgn(c) != 0) return sgn(c);
  return 0;
}

std::vector<RootInterval> isolate_roots(const Bernstein<Rational>& p, const RootOptions& options) {
  CMR_CHECK(options.tolerance > 0 && options.tolerance <= 1);
  if (is_zero(p)) return {};
  // Enclosures of width 2^-bits <= tolerance.
  const int bits = static_cast<int>(std::ceil(-std::log2(options.tolerance)));

  std::vector<Found> found;
  std::vector<SignOracle> oracles;
  if (isolate(p, 0, kIsolationDepth, found)) {
    oracles.emplace_back(p);
    for (Found& f : found)
      if (f.exact) f.multiplicity = multiplicity_at(p, to_rational(f.at));
  } else {
    found.clear();
    const std::vector<Poly> factors = square_free_factors(power_from_bernstein(p));
    for (std::size_t i = 0; i < factors.size(); ++i) {
      if (factors[i].size() < 2) continue;  // a constant: no roots of multiplicity i + 1
      oracles.emplace_back(bernstein_from_power(factors[i]));
      const std::size_t first = found.size();
      isolate(oracles.back().poly(), static_cast<int>(oracles.size()) - 1, -1, found);
      for (std::size_t k = first; k < found.size(); ++k) found[k].multiplicity = static_cast<int>(i) + 1;
    }
  }
  for (Found& f : found)
    while (!f.exact && f.at.level < bits) bisect(f, oracles[f.poly]);
  separate(found, oracles);

  // Signs: p's sign just right of 0 is known; each root flips it when its
  // multiplicity is odd.
  std::vector<RootInterval> out;
  int s = sign_at_start(p);
  for (const Found& f : found) {
    RootInterval r{lower(f), upper(f), f.multiplicity, 0, 0};
    std::tie(r.sign_before, r.sign_after) = signs_around_root(s, f.multiplicity, r.exact() && sgn(r.lo) == 0);
    out.push_back(std::move(r));
  }
  return out;
}

double double_below(const Rational& x) {
  double d = x.get_d();  // truncates towards zero
  if (Rational(d) > x) d = std::nextafter(d, -std::numeric_limits<double>::infinity());
  return d;
}

double double_above(const Rational& x) {
  double d = x.get_d();
  if (Rational(d) < x) d = std::nextafter(d, std::numeric_limits<double>::infinity());
  return d;
}

double nearest_double(const Rational& x) {
  const double lo = double_below(x), hi = double_above(x);
  if (lo == hi) return lo;
  const int c = cmp(Rational(x - lo), Rational(hi - x));
  if (c != 0) return c < 0 ? lo : hi;
  // A tie: the one whose last mantissa bit is 0 (sign-magnitude, so any sign).
  return (std::bit_cast<std::uint64_t>(lo) & 1) == 0 ? lo : hi;
}

}  // namespace cmr
