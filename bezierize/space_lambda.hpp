#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
// Curvature and torsion of a polynomial space curve in Bernstein form: the 3D
// analogue of lambda.hpp (issue 25; Saito & Yoshida 2023 for the route).
//
// P(t) = sum_i B_i^n P_i in R^3, n >= 2; Q = P' the hodograph, degree
// m = n-1, points q_i = n (P_{i+1} - P_i) (space_hodograph).
//
//  c = P' x P''                     degree 2n-4
//     Each component is a 2x2 Wronskian of two coordinates of Q, so the
//     formula of eta (lambda.hpp) holds componentwise with the cross product:
//       c_k = sum_{i<j, i+j-1=k} (j-i) C(m,i) C(m,j) / C(2m-2,k) (q_i x q_j).
//  |c|^2 = c.c                      degree 4n-8   (sum of the components' squares)
//  g = |P'|^2                       degree 2n-2   (speed2_bernstein's formula in 3D)
//  kappa^2 = |c|^2 / g^3, so d(kappa^2)/dt = lambda3 / g^4 with
//  lambda3 = (|c|^2)' g - 3 |c|^2 g'  degree 6n-11: (4n-9)+(2n-2) and
//     (4n-8)+(2n-3) are both 6n-11, and the leading power coefficient is
//     L_c L_g ((4n-8) - 3(2n-2)) = -(2n+2) L_c L_g != 0, so the degree is
//     exact (n = 2: |c|^2 is constant, lambda3 = -3 |c|^2 g', degree 1).
//     Where P' != 0, sign(lambda3) = sign(d kappa / dt) (kappa >= 0 is
//     unsigned in space). For a planar curve c = (0, 0, eta), |c|^2 = eta^2
//     and lambda3 = 2 eta (eta' g - (3/2) eta g') = 2 eta lambda: the sign
//     of d|kappa|/dt of the plane.
//  N = c . P''' = det(P', P'', P''')  degree 3n-9 (n >= 3; 0 for n = 2):
//     a 3x3 Wronskian of the coordinates of Q. Taking coordinates with
//     distinct degrees n-1, n-2, n-3 (a linear change of coordinates scales
//     N by a constant), the degree is (n-1)+(n-2)+(n-3) - (0+1+2) = 3n-9.
//     The product c . P''' is formed at degree (2n-4)+(n-3) = 3n-7 and
//     reduced twice (bernstein_reduce; exactly checked in rationals).
//  tau = N / |c|^2, so d tau/dt has the sign of
//  T = N' |c|^2 - N (|c|^2)'         degree 7n-18 (n >= 3): (3n-10)+(4n-8)
//     and (3n-9)+(4n-9); the leading coefficient is L_N L_c ((3n-9)-(4n-8))
//     = -(n+1) L_N L_c, so the degree is exact where N has full degree.
//     (n = 3: N is constant and T = -N (|c|^2)', degree 3.) The issue's
//     estimate 7n-15 counted N at degree 3n-7 and no cancellation in
//     N'|c|^2 - N(|c|^2)'; tests/bezierize/gen_space_reference.py checks
//     7n-18 on seeded curves of degree 3..7 in exact arithmetic.
// Every coefficient is a polynomial expression of the control points with
// exact rational weights, so T = Rational gives the exact coefficients and
// T = Bounded certified ones (scalar.hpp).
//
// Rational space curves (the second half of this file). C = X / W with the
// homogeneous Bezier curve H = (X, W) = sum_i B_i^n (w_i P_i, w_i), all
// w_i > 0 (spline/space.hpp), so W > 0 on [0, 1]. As in the plane
// (rational_lambda.hpp):
//   C'  = h / W^2,   h = W X' - W' X  (3 components),  h' = W X'' - W'' X,
//   C'' = (h' W^2 - 2 W W' h) / W^4, so C' x C'' = (h x h') / W^4, and
//   h x h' = W e with
//   e = W (X' x X'') - W' (X x X'') + W'' (X x X')   degree 3n-6:
//     e's components are the 3x3 minors of [H H' H''] that hold the W row
//     (for a planar curve e = (0, 0, D), D of rational_lambda.hpp), 3x3
//     Wronskians of degree-n polynomials: degree 3 (n - 3 + 1) = 3n-6,
//     not the nominal 3n-3 (Wronskian degree bound, rational_lambda.hpp).
//   So C' x C'' = e / W^3 and, with E = |e|^2 (degree 6n-12) and
//   G = |h|^2 (degree 4n-4: h is a 2x2 Wronskian, 2n-2),
//     kappa^2 = |C' x C''|^2 / |C'|^6 = E W^6 / G^3,
//     d(kappa^2)/dt = W^5 / G^4 * lambda3r,
//     lambda3r = (E' W + 6 E W') G - 3 E W G'.
//   W^5 > 0 and G > 0 on a regular segment, so sign(lambda3r) =
//   sign(d kappa / dt). Degree: the three products have nominal degree
//   (6n-13)+n+(4n-4) = 11n-17; with leading terms E ~ e t^(6n-12),
//   W ~ w t^n, G ~ g t^(4n-4) their leading coefficients are
//   (6n-12) + 6n - 3 (4n-4) = 0 times e w g, so lambda3r has degree
//   11n-18 (the bound). It is exact: for a planar curve E = D^2
//   and lambda3r = 2 D lambda with lambda of degree 8n-12
//   (rational_lambda.hpp), 3n-6 + 8n-12 = 11n-18, and the generator checks
//   11n-18 on seeded genuine space curves of degree 2..7. For W == 1,
//   e = c, G = g and lambda3r = lambda3 (elevated to 11n-18).
//   kappa = 0 exactly where e = 0 (E = 0); C' = 0 exactly where G = 0.
// Torsion. Removing multiples of the column H = W (C, 1) from H', H'', H'''
// leaves W (C', 0), W (C'', 0), W (C''', 0), so
//   det4(H, H', H'', H''') = -W^4 det(C', C'', C''')
// (expansion along the W row), and tau = det(C', C'', C''') / |C' x C''|^2
// = W^2 Nr / E with
//   Nr = -det4(H, H', H'', H''')   degree 4n-12 (a 4x4 Wronskian,
//     4 (n - 3); n = 3: constant; n = 2: 0). For W == 1, Nr = N.
//   d tau / dt = W / E^2 * Tr,
//   Tr = (2 W' Nr + W Nr') E - W Nr E'   degree 11n-26: nominal
//     (n-1)+(4n-12)+(6n-12) = 11n-25, leading coefficients
//     2n + (4n-12) - (6n-12) = 0. sign(Tr) = sign(d tau / dt) where E > 0,
//     sign(tau) = sign(Nr).
// Computed in Bernstein form only: e at nominal degree 3n-3 reduced three
// times, h at 2n-1 reduced once, lambda3r at 11n-17 reduced once; det4 by
// Laplace expansion into the 2x2 minors of (H, H') (reduced once to 2n-2,
// Wronskians) times those of (H'', H''') (degree 2n-5), at 4n-7 reduced five
// times; Tr at 11n-25 reduced once. bernstein_reduce checks each exact drop
// in rationals; tests/bezierize/gen_space_reference.py recomputes all of them
// in the monomial basis with fractions.
#include <array>
#include <vector>

#include "numeric/bernstein.hpp"
#include "bezierize/lambda.hpp"
#include "bezierize/rational_lambda.hpp"
#include "spline/space.hpp"
#include "spline/vec2.hpp"

namespace cmr {

/// The point type of space curves for scalar T: glm::dvec3 for double,
/// Vec3T<T> otherwise (the same types as HPoint).
template <class T>
using Point3 = HPoint<T>;

template <class P>
auto dot3(const P& a, const P& b) -> std::remove_cvref_t<decltype(a.x)> {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class P>
P cross3(const P& a, const P& b) {
  return P{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// q_i = n (P_{i+1} - P_i), the hodograph of a space curve.
template <class T>
std::vector<Point3<T>> space_hodograph(const std::vector<Point3<T>>& P) {
  const int n = static_cast<int>(P.size()) - 1;
  std::vector<Point3<T>> q;
  q.reserve(n);
  for (int i = 0; i < n; ++i) q.push_back(T(n) * (P[i + 1] - P[i]));
  return q;
}

/// The three components of c = P' x P'' in Bernstein form, degree 2n-4.
template <class T>
std::array<Bernstein<T>, 3> binormal_bernstein(const std::vector<Point3<T>>& P) {
  const std::vector<Point3<T>> q = space_hodograph<T>(P);
  const int m = static_cast<int>(q.size()) - 1;
  std::array<Bernstein<T>, 3> c;
  for (auto& ck : c) ck.assign(2 * m - 1, T(0));
  for (int i = 0; i <= m; ++i)
    for (int j = i + 1; j <= m; ++j) {
      const int k = i + j - 1;
      const T w = Scalar<T>::ratio(static_cast<Int128>(j - i) * binomial(m, i) * binomial(m, j), binomial(2 * m - 2, k));
      const Point3<T> x = cross3(q[i], q[j]);
      c[0][k] += w * x.x;
      c[1][k] += w * x.y;
      c[2][k] += w * x.z;
    }
  return c;
}

/// |c|^2 in Bernstein form, degree 4n-8.
template <class T>
Bernstein<T> binormal_norm2(const std::array<Bernstein<T>, 3>& c) {
  Bernstein<T> s = bernstein_product(c[0], c[0]);
  const Bernstein<T> y = bernstein_product(c[1], c[1]), z = bernstein_product(c[2], c[2]);
  for (std::size_t k = 0; k < s.size(); ++k) s[k] = s[k] + y[k] + z[k];
  return s;
}

/// g = |P'|^2 in Bernstein form, degree 2n-2.
template <class T>
Bernstein<T> space_speed2_bernstein(const std::vector<Point3<T>>& P) {
  const std::vector<Point3<T>> q = space_hodograph<T>(P);
  const int m = static_cast<int>(q.size()) - 1;
  Bernstein<T> g(2 * m + 1, T(0));
  for (int i = 0; i <= m; ++i)
    for (int j = i; j <= m; ++j) {
      const Int128 num = (i == j ? 1 : 2) * binomial(m, i) * binomial(m, j);
      g[i + j] += Scalar<T>::ratio(num, binomial(2 * m, i + j)) * dot3(q[i], q[j]);
    }
  return g;
}

/// a' b - 3 a b' at the common degree (a' may be the empty polynomial).
template <class T>
Bernstein<T> space_wronskian_combination(const Bernstein<T>& a, const Bernstein<T>& b, const T& factor) {
  const Bernstein<T> x = bernstein_product(bernstein_derivative(a), b);
  const Bernstein<T> y = bernstein_product(a, bernstein_derivative(b));
  if (y.empty()) return x;
  Bernstein<T> r(y.size(), T(0));
  for (std::size_t k = 0; k < r.size(); ++k) r[k] = (x.empty() ? T(0) : x[k]) - factor * y[k];
  return r;
}

/// Everything a space segment's analysis needs, from its Bezier points.
template <class T>
struct SpacePolynomials {
  std::array<Bernstein<T>, 3> c;  ///< P' x P'', degree 2n-4
  Bernstein<T> c2;                ///< |c|^2, degree 4n-8
  Bernstein<T> g;                 ///< |P'|^2, degree 2n-2
  Bernstein<T> lambda3;           ///< (|c|^2)' g - 3 |c|^2 g', degree 6n-11
};

template <class T>
SpacePolynomials<T> space_polynomials(const std::vector<Point3<T>>& P) {
  SpacePolynomials<T> r;
  r.c = binormal_bernstein<T>(P);
  r.c2 = binormal_norm2<T>(r.c);
  r.g = space_speed2_bernstein<T>(P);
  r.lambda3 = space_wronskian_combination<T>(r.c2, r.g, T(3));
  return r;
}

/// lambda3 alone, degree 6n-11.
template <class T>
Bernstein<T> lambda3_bernstein(const std::vector<Point3<T>>& P) {
  return space_polynomials<T>(P).lambda3;
}

/// N = det(P', P'', P''') = c . P''' in Bernstein form, degree 3n-9; empty
/// (identically zero) for n = 2.
template <class T>
Bernstein<T> torsion_numerator_bernstein(const std::vector<Point3<T>>& P) {
  const int n = static_cast<int>(P.size()) - 1;
  if (n < 3) return {};
  const std::array<Bernstein<T>, 3> c = binormal_bernstein<T>(P);
  const std::vector<Point3<T>> r = space_hodograph<T>(space_hodograph<T>(space_hodograph<T>(P)));
  std::array<Bernstein<T>, 3> rc;
  for (const Point3<T>& p : r) {
    rc[0].push_back(p.x);
    rc[1].push_back(p.y);
    rc[2].push_back(p.z);
  }
  Bernstein<T> s = bernstein_product(c[0], rc[0]);
  const Bernstein<T> y = bernstein_product(c[1], rc[1]), z = bernstein_product(c[2], rc[2]);
  for (std::size_t k = 0; k < s.size(); ++k) s[k] = s[k] + y[k] + z[k];
  return bernstein_reduce(bernstein_reduce(s));  // 3n-7 -> 3n-9
}

/// T = N' |c|^2 - N (|c|^2)', the sign of d tau / dt, degree 7n-18; empty for
/// n = 2 (a quadratic is planar: tau == 0).
template <class T>
Bernstein<T> torsion_sign_bernstein(const std::vector<Point3<T>>& P) {
  const Bernstein<T> N = torsion_numerator_bernstein<T>(P);
  if (N.empty()) return {};
  const Bernstein<T> c2 = binormal_norm2<T>(binormal_bernstein<T>(P));
  return space_wronskian_combination<T>(N, c2, T(1));
}

// ---- rational space curves (homogeneous points (w x, w y, w z, w)) ----

namespace space_rational_detail {

using rational_detail::add;
using rational_detail::minor;
using rational_detail::reduce;

template <class T>
using BVec3 = std::array<Bernstein<T>, 3>;

/// a x b for vectors of Bernstein polynomials.
template <class T>
BVec3<T> cross(const BVec3<T>& a, const BVec3<T>& b) {
  return {minor(a[1], b[2], a[2], b[1]), minor(a[2], b[0], a[0], b[2]), minor(a[0], b[1], a[1], b[0])};
}

template <class T>
BVec3<T> derivative(const BVec3<T>& a) {
  return {bernstein_derivative(a[0]), bernstein_derivative(a[1]), bernstein_derivative(a[2])};
}

/// |a|^2 (the empty polynomial when a == 0 structurally).
template <class T>
Bernstein<T> norm2(const BVec3<T>& a) {
  return add(add(bernstein_product(a[0], a[0]), bernstein_product(a[1], a[1]), T(1)), bernstein_product(a[2], a[2]),
             T(1));
}

/// The coordinate polynomials X (three) and W of homogeneous Bezier points.
template <class T>
void components(const std::vector<HPoint3<T>>& H, BVec3<T>& X, Bernstein<T>& W) {
  for (const HPoint3<T>& p : H) {
    X[0].push_back(p.x);
    X[1].push_back(p.y);
    X[2].push_back(p.z);
    W.push_back(p.w);
  }
}

/// An empty (structurally zero) polynomial as `size` zero coefficients.
template <class T>
Bernstein<T> sized(Bernstein<T> p, int size) {
  if (p.empty()) p.assign(static_cast<std::size_t>(size), T(0));
  return p;
}

}  // namespace space_rational_detail

/// e = W (X' x X'') - W' (X x X'') + W'' (X x X') at degree 3n-6 (n >= 2):
/// C' x C'' = e / W^3.
template <class T>
std::array<Bernstein<T>, 3> binormal_bernstein(const std::vector<HPoint3<T>>& H) {
  using namespace space_rational_detail;
  BVec3<T> X;
  Bernstein<T> W;
  components<T>(H, X, W);
  const BVec3<T> X1 = derivative<T>(X), X2 = derivative<T>(X1);
  const Bernstein<T> W1 = bernstein_derivative(W), W2 = bernstein_derivative(W1);
  const BVec3<T> a = cross<T>(X1, X2), b = cross<T>(X, X2), c = cross<T>(X, X1);
  const int n = static_cast<int>(H.size()) - 1;
  BVec3<T> e;
  for (int k = 0; k < 3; ++k) {
    Bernstein<T> v = add(add(bernstein_product(W, a[k]), bernstein_product(W1, b[k]), T(-1)),
                         bernstein_product(W2, c[k]), T(1));
    e[k] = sized(reduce(std::move(v), 3), 3 * n - 5);
  }
  return e;
}

/// h = W X' - W' X at degree 2n-2: C' = h / W^2.
template <class T>
std::array<Bernstein<T>, 3> rational_space_h_bernstein(const std::vector<HPoint3<T>>& H) {
  using namespace space_rational_detail;
  BVec3<T> X;
  Bernstein<T> W;
  components<T>(H, X, W);
  const Bernstein<T> W1 = bernstein_derivative(W);
  const int n = static_cast<int>(H.size()) - 1;
  BVec3<T> h;
  for (int k = 0; k < 3; ++k)
    h[k] = sized(reduce(minor(W, bernstein_derivative(X[k]), W1, X[k]), 1), 2 * n - 1);
  return h;
}

/// G = |h|^2 at degree 4n-4: zero exactly where C' = 0.
template <class T>
Bernstein<T> space_speed2_bernstein(const std::vector<HPoint3<T>>& H) {
  const int n = static_cast<int>(H.size()) - 1;
  return space_rational_detail::sized(space_rational_detail::norm2<T>(rational_space_h_bernstein<T>(H)), 4 * n - 3);
}

/// The rational curve's polynomials in SpacePolynomials' slots: c = e
/// (3n-6), c2 = E = |e|^2 (6n-12), g = G = |h|^2 (4n-4),
/// lambda3 = lambda3r = (E' W + 6 E W') G - 3 E W G' (11n-18).
template <class T>
SpacePolynomials<T> space_polynomials(const std::vector<HPoint3<T>>& H) {
  using namespace space_rational_detail;
  const int n = static_cast<int>(H.size()) - 1;
  SpacePolynomials<T> r;
  r.c = binormal_bernstein<T>(H);
  r.c2 = sized(norm2<T>(r.c), 6 * n - 11);
  r.g = space_speed2_bernstein<T>(H);
  BVec3<T> X;
  Bernstein<T> W;
  components<T>(H, X, W);
  const Bernstein<T> W1 = bernstein_derivative(W);
  // (E' W + 6 E W') G - 3 E W G'
  const Bernstein<T> a = add(bernstein_product(bernstein_derivative(r.c2), W), bernstein_product(r.c2, W1), T(6));
  Bernstein<T> l = add(bernstein_product(a, r.g), bernstein_product(bernstein_product(r.c2, W), bernstein_derivative(r.g)),
                       T(-3));
  r.lambda3 = reduce(std::move(l), 1);
  return r;
}

template <class T>
Bernstein<T> lambda3_bernstein(const std::vector<HPoint3<T>>& H) {
  return space_polynomials<T>(H).lambda3;
}

/// Nr = -det4(H, H', H'', H''') at degree 4n-12 (tau = W^2 Nr / E); empty
/// for n = 2.
template <class T>
Bernstein<T> torsion_numerator_bernstein(const std::vector<HPoint3<T>>& H) {
  using namespace space_rational_detail;
  const int n = static_cast<int>(H.size()) - 1;
  if (n < 3) return {};
  BVec3<T> X;
  Bernstein<T> W;
  components<T>(H, X, W);
  const std::array<Bernstein<T>, 4> h0{X[0], X[1], X[2], W};
  std::array<Bernstein<T>, 4> h1, h2, h3;
  for (int i = 0; i < 4; ++i) {
    h1[i] = bernstein_derivative(h0[i]);
    h2[i] = bernstein_derivative(h1[i]);
    h3[i] = bernstein_derivative(h2[i]);
  }
  // Laplace expansion along the column pairs (H, H') and (H'', H'''):
  // rows i < j, sign (-1)^(i+j+1), complement rows k < l.
  const auto m = [&](int i, int j) { return reduce(minor(h0[i], h1[j], h0[j], h1[i]), 1); };  // 2n-2
  const auto M = [&](int i, int j) { return minor(h2[i], h3[j], h2[j], h3[i]); };               // 2n-5
  Bernstein<T> d = bernstein_product(m(0, 1), M(2, 3));
  d = add(d, bernstein_product(m(0, 2), M(1, 3)), T(-1));
  d = add(d, bernstein_product(m(0, 3), M(1, 2)), T(1));
  d = add(d, bernstein_product(m(1, 2), M(0, 3)), T(1));
  d = add(d, bernstein_product(m(1, 3), M(0, 2)), T(-1));
  d = add(d, bernstein_product(m(2, 3), M(0, 1)), T(1));
  d = sized(std::move(d), 4 * n - 6);
  d = reduce(std::move(d), 5);
  for (T& x : d) x = T(0) - x;
  return d;
}

/// Tr = (2 W' Nr + W Nr') E - W Nr E' at degree 11n-26, the sign of
/// d tau / dt; empty for n = 2 (a conic is planar: tau == 0).
template <class T>
Bernstein<T> torsion_sign_bernstein(const std::vector<HPoint3<T>>& H) {
  using namespace space_rational_detail;
  const Bernstein<T> N = torsion_numerator_bernstein<T>(H);
  if (N.empty()) return {};
  const int n = static_cast<int>(H.size()) - 1;
  BVec3<T> X;
  Bernstein<T> W;
  components<T>(H, X, W);
  const Bernstein<T> E = sized(norm2<T>(binormal_bernstein<T>(H)), 6 * n - 11);
  // a = 2 W' N + W N' (the empty N' of a constant N is handled by add).
  Bernstein<T> a = add(bernstein_product(bernstein_derivative(W), N), bernstein_product(W, bernstein_derivative(N)),
                       Scalar<T>::ratio(1, 2));
  for (T& x : a) x = T(2) * x;
  Bernstein<T> t = add(bernstein_product(a, E), bernstein_product(bernstein_product(W, N), bernstein_derivative(E)), T(-1));
  return reduce(sized(std::move(t), 11 * n - 24), 1);
}

}  // namespace cmr
