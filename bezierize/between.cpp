#include "bezierize/between.hpp"

#include <cmath>
#include <optional>

#include "bezierize/algorithms.hpp"
#include "numeric/bernstein.hpp"
#include "bezierize/lambda.hpp"
#include "numeric/roots.hpp"
#include "numeric/scalar.hpp"
#include "spline/errors.hpp"

namespace cmr {

const char* to_string(BetweenVerdict::Kind k) {
  switch (k) {
    case BetweenVerdict::Kind::holds_throughout: return "holds-throughout";
    case BetweenVerdict::Kind::fails: return "fails";
    case BetweenVerdict::Kind::undecided: return "undecided";
  }
  return "?";
}

namespace {

enum class Which { lambda, eta };

int s_degree(Which w) { return w == Which::lambda ? 4 : 2; }

void check_masters(const std::vector<Vec2>& A, const std::vector<Vec2>& B) {
  if (A.size() != B.size()) {
    std::string m = "between masters: the masters have ";
    m.append(std::to_string(A.size())).append(" and ").append(std::to_string(B.size()));
    m.append(" control points (incompatible)");
    throw InputError(m);
  }
  if (A.size() < 3 || A.size() > static_cast<std::size_t>(kMaxDegree) + 1) {
    std::string m = "between masters: a piece needs 3 to ";
    m.append(std::to_string(kMaxDegree + 1)).append(" control points, not ").append(std::to_string(A.size()));
    throw InputError(m);
  }
  for (std::size_t i = 0; i < A.size(); ++i)
    if (!std::isfinite(A[i].x) || !std::isfinite(A[i].y) || !std::isfinite(B[i].x) || !std::isfinite(B[i].y)) {
      std::string m = "between masters: control point ";
      m.append(std::to_string(i)).append(" is not finite");
      throw InputError(m);
    }
}

void check_options(const BetweenOptions& o) {
  if (o.max_depth < 0 || o.max_depth > kMaxDepth || o.s_depth < 0 || o.s_depth > 48 || o.max_cells <= 0) {
    std::string m = "between masters: max_depth must lie in 0..";
    m.append(std::to_string(kMaxDepth)).append(", s_depth in 0..48 and max_cells be positive");
    throw InputError(m);
  }
}

/// The instance P(s) = (1 - s) A + s B in scalar T (s exact).
template <class T>
std::vector<Point<T>> instance(const std::vector<Vec2>& A, const std::vector<Vec2>& B, const T& s) {
  const T r = T(1) - s;
  std::vector<Point<T>> P;
  P.reserve(A.size());
  for (std::size_t i = 0; i < A.size(); ++i) P.push_back(r * to_point<T>(A[i]) + s * to_point<T>(B[i]));
  return P;
}

template <class T>
Bernstein<T> t_coefficients(Which w, const std::vector<Point<T>>& P) {
  return w == Which::lambda ? lambda_bernstein<T>(P) : eta_bernstein<T>(P);
}

/// (M^-1) for M_kj = B_j^d(k/d), k, j = 0..d, exactly (Gauss-Jordan), row-major.
std::vector<Rational> inverse_collocation(int d) {
  const int n = d + 1;
  std::vector<Rational> M(static_cast<std::size_t>(n * n)), I(static_cast<std::size_t>(n * n));
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j) {
      Rational x = Scalar<Rational>::ratio(binomial(d, j), 1);
      for (int a = 0; a < j; ++a) x *= Scalar<Rational>::ratio(k, d);
      for (int a = 0; a < d - j; ++a) x *= Scalar<Rational>::ratio(d - k, d);
      M[k * n + j] = x;
      I[k * n + j] = k == j ? 1 : 0;
    }
  for (int col = 0; col < n; ++col) {
    int piv = col;
    while (M[piv * n + col] == 0) ++piv;  // M is invertible (distinct nodes)
    for (int j = 0; j < n; ++j) {
      std::swap(M[col * n + j], M[piv * n + j]);
      std::swap(I[col * n + j], I[piv * n + j]);
    }
    const Rational p = M[col * n + col];
    for (int j = 0; j < n; ++j) {
      M[col * n + j] /= p;
      I[col * n + j] /= p;
    }
    for (int r = 0; r < n; ++r) {
      if (r == col || M[r * n + col] == 0) continue;
      const Rational f = M[r * n + col];
      for (int j = 0; j < n; ++j) {
        M[r * n + j] -= f * M[col * n + j];
        I[r * n + j] -= f * I[col * n + j];
      }
    }
  }
  return I;
}

template <class T>
T from_rational(const Rational& q);
template <>
Rational from_rational<Rational>(const Rational& q) {
  return q;
}
template <>
Bounded from_rational<Bounded>(const Rational& q) {
  if (q == 0) return Bounded(0.0);
  const mpz_class num = abs(q.get_num()), den = q.get_den();
  CMR_CHECK(num.fits_ulong_p() && den.fits_ulong_p());
  const Bounded b = Scalar<Bounded>::ratio(num.get_ui(), den.get_ui());
  return sgn(q) < 0 ? -b : b;
}

/// Tensor-product Bernstein coefficients, c[i * ns + j] for B_i(t) B_j(s).
template <class T>
struct Tensor {
  int nt = 0, ns = 0;
  std::vector<T> c;
};

template <class T>
Tensor<T> build_tensor(Which w, const std::vector<Vec2>& A, const std::vector<Vec2>& B) {
  const int d = s_degree(w);
  static const std::vector<Rational> inv2 = inverse_collocation(2), inv4 = inverse_collocation(4);
  const std::vector<Rational>& inv = d == 2 ? inv2 : inv4;
  std::vector<Bernstein<T>> rows;
  for (int k = 0; k <= d; ++k) {
    T s;
    if constexpr (Scalar<T>::exact) s = Scalar<Rational>::ratio(k, d);
    else s = T(static_cast<double>(k) / d);  // k/2, k/4: exact doubles
    rows.push_back(t_coefficients<T>(w, instance<T>(A, B, s)));
  }
  Tensor<T> out;
  out.nt = static_cast<int>(rows[0].size());
  out.ns = d + 1;
  out.c.assign(static_cast<std::size_t>(out.nt * out.ns), T(0));
  for (int i = 0; i < out.nt; ++i)
    for (int j = 0; j <= d; ++j) {
      T x(0);
      for (int k = 0; k <= d; ++k) x += from_rational<T>(inv[j * (d + 1) + k]) * rows[k][i];
      out.c[i * out.ns + j] = x;
    }
  return out;
}

enum class Axis { t, s };

/// Halves c at 1/2 in one variable (de Casteljau, bernstein_halve per line).
template <class T>
void halve(const Tensor<T>& c, Axis axis, Tensor<T>& left, Tensor<T>& right) {
  left = c;
  right = c;
  const int lines = axis == Axis::t ? c.ns : c.nt, len = axis == Axis::t ? c.nt : c.ns;
  const int stride = axis == Axis::t ? c.ns : 1, step = axis == Axis::t ? 1 : c.ns;
  std::vector<T> line(len), l(len), r(len), work(len);
  for (int a = 0; a < lines; ++a) {
    for (int k = 0; k < len; ++k) line[k] = c.c[a * step + k * stride];
    bernstein_halve(line.data(), static_cast<std::size_t>(len), l.data(), r.data(), work.data());
    for (int k = 0; k < len; ++k) {
      left.c[a * step + k * stride] = l[k];
      right.c[a * step + k * stride] = r[k];
    }
  }
}

/// The sub-cell (level, index) of c along one axis, by halving.
template <class T>
Tensor<T> descend(Tensor<T> c, Axis axis, int level, std::uint64_t index) {
  Tensor<T> l, r;
  for (int b = level - 1; b >= 0; --b) {
    halve(c, axis, l, r);
    c = ((index >> b) & 1) ? std::move(r) : std::move(l);
  }
  return c;
}

/// Monomial coefficients (lowest first) of a polynomial in Bernstein form:
/// a_k = sum_{j<=k} C(d,j) C(d-j,k-j) (-1)^(k-j) c_j.
std::vector<Rational> to_monomial(const Bernstein<Rational>& c) {
  const int d = static_cast<int>(c.size()) - 1;
  std::vector<Rational> a(c.size(), Rational(0));
  for (int k = 0; k <= d; ++k)
    for (int j = 0; j <= k; ++j) {
      const Rational w = Scalar<Rational>::ratio(binomial(d, j) * binomial(d - j, k - j), 1);
      if ((k - j) % 2 == 0) a[k] += w * c[j];
      else a[k] -= w * c[j];
    }
  return a;
}

/// Bernstein coefficients of degree D of a polynomial given by monomials of
/// degree <= D: b_k = sum_{i<=k} C(k,i)/C(D,i) a_i.
Bernstein<Rational> to_bernstein(const std::vector<Rational>& a, int D) {
  Bernstein<Rational> b(static_cast<std::size_t>(D + 1), Rational(0));
  for (int k = 0; k <= D; ++k)
    for (int i = 0; i <= k && i < static_cast<int>(a.size()); ++i)
      b[k] += Scalar<Rational>::ratio(binomial(k, i), binomial(D, i)) * a[i];
  return b;
}

void trim(std::vector<Rational>& a) {
  while (!a.empty() && a.back() == 0) a.pop_back();
}

/// a = q b + r (b non-zero, trimmed); returns q, leaves r in a.
std::vector<Rational> divide(std::vector<Rational>& a, const std::vector<Rational>& b) {
  trim(a);
  std::vector<Rational> q(a.size() >= b.size() ? a.size() - b.size() + 1 : 0, Rational(0));
  while (a.size() >= b.size()) {
    const std::size_t shift = a.size() - b.size();
    const Rational f = a.back() / b.back();
    q[shift] = f;
    for (std::size_t k = 0; k < b.size(); ++k) a[shift + k] -= f * b[k];
    a.pop_back();  // the leading term is now 0
    trim(a);
  }
  return q;
}

/// The Tensor's s-rows divided by their gcd h(s) when deg h >= 1 (nullopt
/// otherwise); h_sign: the sign of h on [0, 1], 0 when it changes there.
std::optional<Tensor<Rational>> divide_common_factor(const Tensor<Rational>& c, int& h_sign) {
  std::vector<std::vector<Rational>> rows;
  std::vector<Rational> g;
  for (int i = 0; i < c.nt; ++i) {
    rows.push_back(to_monomial(Bernstein<Rational>(c.c.begin() + i * c.ns, c.c.begin() + (i + 1) * c.ns)));
    trim(rows.back());
    std::vector<Rational> a = rows.back(), b = g;  // Euclid: g = gcd(g, row)
    while (!b.empty()) {
      divide(a, b);
      std::swap(a, b);
    }
    g = a;
  }
  if (g.size() < 2) return std::nullopt;  // a constant (or lambda == 0)
  const int dh = static_cast<int>(g.size()) - 1, ds = c.ns - 1 - dh;
  Tensor<Rational> mu;
  mu.nt = c.nt;
  mu.ns = ds + 1;
  for (std::vector<Rational>& r : rows) {
    std::vector<Rational> q = r.empty() ? std::vector<Rational>{} : divide(r, g);
    CMR_CHECK(r.empty());  // g divides every row exactly
    const Bernstein<Rational> b = to_bernstein(q, ds);
    mu.c.insert(mu.c.end(), b.begin(), b.end());
  }
  const Bernstein<Rational> h = to_bernstein(g, dh);
  h_sign = sgn(h.front());
  for (const RootInterval& r : isolate_roots(h))
    if (r.sign_change() && r.lo < 1) h_sign = 0;
  return mu;
}

/// Each exact coefficient rounded to a double with its bound (get_d
/// truncates: the error is below one ulp, 2^-52 |v|, charged as 2^-51 |v|).
Tensor<Bounded> rounded(const Tensor<Rational>& c) {
  Tensor<Bounded> out;
  out.nt = c.nt;
  out.ns = c.ns;
  for (const Rational& q : c.c) {
    const double v = q.get_d();
    out.c.push_back(q == 0 ? Bounded(0.0) : Bounded(v, 2 * Bounded::kRound * std::fabs(v) + Bounded::kTiny));
  }
  return out;
}

/// A cell's outcome: every coefficient certainly >= 0 (eta: > 0), <= 0
/// (eta: < 0), all 0 (lambda only), split, or a sign the bound leaves open.
enum class Cell { up, down, zero, split, uncertain };

template <class T>
Cell decide(Which w, const Tensor<T>& c) {
  int pos = 0, neg = 0, zero = 0, unknown = 0;
  for (const T& x : c.c) {
    const int g = Scalar<T>::sign(x);
    if (g == kSignUnknown) ++unknown;
    else if (g > 0) ++pos;
    else if (g < 0) ++neg;
    else ++zero;
  }
  const int all = static_cast<int>(c.c.size());
  if (pos > 0 && neg > 0) return Cell::split;
  if (unknown > 0) return Cell::uncertain;
  if (w == Which::lambda) {
    if (zero == all) return Cell::zero;
    if (neg == 0) return Cell::up;
    if (pos == 0) return Cell::down;
  } else {
    if (pos == all) return Cell::up;
    if (neg == all) return Cell::down;
  }
  return Cell::split;
}

/// The t-cells of one s-interval, folded: certified when no cell was left
/// undecided and not both directions occurred.
struct Fold {
  bool up = false, down = false, undecided = false;
  bool stop() const { return undecided || (up && down); }
  bool certified() const { return !stop(); }
};

class Search {
 public:
  Search(Which w, const std::vector<Vec2>& A, const std::vector<Vec2>& B, const BetweenOptions& o)
      : w_(w), A_(A), B_(B), o_(o) {}

  BetweenVerdict run() {
    bool all = s_cell(build_tensor<Bounded>(w_, A_, B_), 0, 0);
    int h_sign = 1;  // sign of the common factor h(s) on [0, 1], 0 when it changes
    if (!all && !budget_spent_ && w_ == Which::lambda) {
      // lambda = h(s) mu(t, s) with h the gcd of the rows in s: where h has a
      // root between the masters (an instance with lambda == 0, a straight
      // one), no interval around it can be certified on lambda; on mu it can.
      exact_root_ = build_tensor<Rational>(w_, A_, B_);
      if (std::optional<Tensor<Rational>> mu = divide_common_factor(*exact_root_, h_sign)) {
        exact_root_ = std::move(*mu);
        up_ = down_ = false;
        v_.s_lower = 0;
        all = s_cell(rounded(*exact_root_), 0, 0);
      }
    }
    if (all) {
      v_.kind = BetweenVerdict::Kind::holds_throughout;
      v_.s_lower = 1;
      if (h_sign < 0) std::swap(up_, down_);
      v_.direction = h_sign != 0 && up_ && !down_ ? 1 : (h_sign != 0 && down_ && !up_ ? -1 : 0);
      return v_;
    }
    if (!budget_spent_) find_witness();
    return v_;
  }

 private:
  /// Phase 1: certifies s-intervals left to right, depth first; returns true
  /// when every s-interval of this subtree is certified, false at the first
  /// one that is not (s_lower is then its left end).
  bool s_cell(const Tensor<Bounded>& c, int level, std::uint64_t index) {
    level_ = level;
    index_ = index;
    exact_s_.reset();
    Fold f;
    t_cell(c, 0, 0, f);
    if (f.certified()) {
      up_ = up_ || f.up;
      down_ = down_ || f.down;
      v_.s_lower = std::ldexp(static_cast<double>(index + 1), -level);
      return true;
    }
    if (budget_spent_ || level >= o_.s_depth) return false;
    Tensor<Bounded> l, r;
    halve(c, Axis::s, l, r);
    return s_cell(l, level + 1, 2 * index) && s_cell(r, level + 1, 2 * index + 1);
  }

  const Tensor<Rational>& exact_s_cell() {
    if (!exact_root_) exact_root_ = build_tensor<Rational>(w_, A_, B_);
    if (!exact_s_) exact_s_ = descend(*exact_root_, Axis::s, level_, index_);
    return *exact_s_;
  }

  template <class T>
  void t_cell(const Tensor<T>& c, int level, std::uint64_t index, Fold& f) {
    if (++cells_ > o_.max_cells) {
      budget_spent_ = true;
      f.undecided = true;
      return;
    }
    Cell d = decide(w_, c);
    if constexpr (!Scalar<T>::exact) {
      if (d == Cell::uncertain) {
        --cells_;  // the exact subtree counts this cell again
        t_cell(descend(exact_s_cell(), Axis::t, level, index), level, index, f);
        return;
      }
      ++v_.cells_float;
    } else {
      ++v_.cells_exact;
    }
    switch (d) {
      case Cell::up: f.up = true; return;
      case Cell::down: f.down = true; return;
      case Cell::zero: return;
      case Cell::uncertain: f.undecided = true; return;  // not reached in exact arithmetic
      case Cell::split: break;
    }
    if (level >= o_.max_depth) {
      f.undecided = true;
      return;
    }
    Tensor<T> l, r;
    halve(c, Axis::t, l, r);
    t_cell(l, level + 1, 2 * index, f);
    if (!f.stop()) t_cell(r, level + 1, 2 * index + 1, f);
  }

  /// Does the single-piece classifier fail at s (exactly)? Bounded first,
  /// rationals where the bound does not decide, or always with `exact`.
  bool fails_at(double s, bool exact) {
    ++v_.witnesses_tried;
    if (!exact) {
      const std::vector<Point<Bounded>> P = instance<Bounded>(A_, B_, Bounded(s));
      if (auto r = verdict_fails(t_coefficients<Bounded>(w_, P))) return *r;
    }
    return *verdict_fails(t_coefficients<Rational>(w_, instance<Rational>(A_, B_, Rational(s))));
  }

  template <class T>
  std::optional<bool> verdict_fails(const Bernstein<T>& p) const {
    if (w_ == Which::lambda) {
      const auto r = algorithm1(p, o_.max_depth);
      if (!r) return std::nullopt;
      return r->curvature == Curvature::non_monotone;
    }
    const auto r = algorithm2(p, o_.max_depth);
    if (!r) return std::nullopt;
    return r->inflection == Inflection::present;
  }

  /// Phase 2: from s_lower (the left end of the first s-interval not
  /// certified), s_lower + 2^(k - s_depth) for k = 0, 1, ... up to 1, then
  /// bisection between the last one that did not fail and the first that
  /// did; the smallest failing s is checked again in rationals.
  void find_witness() {
    const double lo0 = v_.s_lower, step0 = std::ldexp(1.0, -o_.s_depth);
    std::optional<double> hit;
    double pass = lo0;
    if (fails_at(lo0, false)) hit = lo0;
    for (double step = step0; !hit; step *= 2) {
      const double s = std::min(1.0, lo0 + step);
      if (fails_at(s, false)) hit = s;
      else pass = s;
      if (s >= 1) break;
    }
    if (!hit) return;  // undecided
    double hi = *hit;
    for (int k = 0; k < o_.s_depth + 2 && hi - pass > step0; ++k) {
      const double m = 0.5 * (pass + hi);  // dyadic, exact
      if (fails_at(m, false)) hi = m;
      else pass = m;
    }
    if (!fails_at(hi, true)) return;  // cannot happen: the bounded answer is certain
    v_.kind = BetweenVerdict::Kind::fails;
    v_.s_first_fail = hi;
    const Bernstein<Rational> p = t_coefficients<Rational>(w_, instance<Rational>(A_, B_, Rational(hi)));
    const std::vector<RootInterval> roots = isolate_roots(p);
    const RootInterval* at = roots.empty() ? nullptr : &roots.front();  // eta: a zero at an end
    for (const RootInterval& r : roots)
      if (r.sign_change()) {
        at = &r;
        break;
      }
    if (at) v_.t_witness = nearest_double(Rational((at->lo + at->hi) / 2));
  }

  Which w_;
  const std::vector<Vec2>& A_;
  const std::vector<Vec2>& B_;
  BetweenOptions o_;
  BetweenVerdict v_;
  std::optional<Tensor<Rational>> exact_root_, exact_s_;
  int level_ = 0;
  std::uint64_t index_ = 0;
  std::int64_t cells_ = 0;
  bool budget_spent_ = false, up_ = false, down_ = false;
};

BetweenVerdict between(Which w, const std::vector<Vec2>& A, const std::vector<Vec2>& B, const BetweenOptions& o) {
  check_masters(A, B);
  check_options(o);
  return Search(w, A, B, o).run();
}

BetweenTensor tensor_out(Which w, const std::vector<Vec2>& A, const std::vector<Vec2>& B) {
  check_masters(A, B);
  const Tensor<Rational> e = build_tensor<Rational>(w, A, B);
  const Tensor<Bounded> b = build_tensor<Bounded>(w, A, B);
  BetweenTensor out;
  out.deg_t = e.nt - 1;
  out.deg_s = e.ns - 1;
  for (std::size_t k = 0; k < e.c.size(); ++k) {
    out.exact.push_back(e.c[k].get_str());
    out.value.push_back(b.c[k].v);
    out.error.push_back(b.c[k].e);
  }
  return out;
}

/// Sign of a polynomial in s on all of [0, 1] and its first zero there.
void node_side(const Bernstein<Rational>& p, int& sign, double& zero_s) {
  if (is_zero(p)) {
    sign = 0;
    zero_s = 0;
    return;
  }
  const std::vector<RootInterval> roots = isolate_roots(p);
  if (roots.empty()) {
    sign = sgn(p.front());
    zero_s = -1;
    return;
  }
  sign = 0;
  zero_s = nearest_double(Rational((roots.front().lo + roots.front().hi) / 2));
}

}  // namespace

BetweenVerdict monotone_between(const std::vector<Vec2>& masterA, const std::vector<Vec2>& masterB,
                                const BetweenOptions& options) {
  return between(Which::lambda, masterA, masterB, options);
}

BetweenVerdict inflection_free_between(const std::vector<Vec2>& masterA, const std::vector<Vec2>& masterB,
                                       const BetweenOptions& options) {
  return between(Which::eta, masterA, masterB, options);
}

NodeBetween node_lambda_between(const std::vector<Vec2>& LA, const std::vector<Vec2>& LB,
                                const std::vector<Vec2>& RA, const std::vector<Vec2>& RB) {
  check_masters(LA, LB);
  check_masters(RA, RB);
  const Tensor<Rational> L = build_tensor<Rational>(Which::lambda, LA, LB);
  const Tensor<Rational> R = build_tensor<Rational>(Which::lambda, RA, RB);
  const auto row = [](const Tensor<Rational>& c, int i) {
    return Bernstein<Rational>(c.c.begin() + i * c.ns, c.c.begin() + (i + 1) * c.ns);
  };
  NodeBetween out;
  node_side(row(L, L.nt - 1), out.left_sign, out.left_zero_s);
  node_side(row(R, 0), out.right_sign, out.right_zero_s);
  return out;
}

BetweenTensor lambda_between_tensor(const std::vector<Vec2>& masterA, const std::vector<Vec2>& masterB) {
  return tensor_out(Which::lambda, masterA, masterB);
}

BetweenTensor eta_between_tensor(const std::vector<Vec2>& masterA, const std::vector<Vec2>& masterB) {
  return tensor_out(Which::eta, masterA, masterB);
}

}  // namespace cmr
