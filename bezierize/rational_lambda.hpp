#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
// D and lambda of a rational Bezier segment in Bernstein form: Algorithms 1
// and 2 of CAD&A 2024 §3 for rational curves (the paper's future work).
//
// A rational Bezier segment of degree n is C = X / W with the homogeneous
// curve H(t) = (X, Y, W) = sum_i B_i^n(t) H_i, H_i = (w_i x_i, w_i y_i, w_i),
// any finite weights (bspline.hpp). The formulas below are polynomial (no
// division), so they hold for every segment; they mean curvature where W != 0
// on [0, 1], i.e. on a segment without a pole (analyze.hpp: segment_poles),
// where W has one sign.
//
// Derivation. With X = (X, Y):
//   C'  = (W X' - W' X) / W^2 = h / W^2,        h = W X' - W' X,
//   h'  = W X'' - W'' X                         (the W' X' terms cancel),
//   C'' = (h' W^2 - 2 W W' h) / W^4, so det(C', C'') = det(h, h') / W^4.
//   Expanding D = det(H, H', H'') (3x3) along the W row and using the
//   definition of h gives W D = det(h, h'), hence det(C', C'') = D / W^3 and
//   kappa = det(C', C'') / |C'|^3 = W^3 D / |h|^3.
//   dkappa/dt = [(3 W^2 W' D + W^3 D') |h|^2 - 3 W^3 D (h.h')] / |h|^5
//             = W^2 lambda / |h|^5,
//   lambda = (3 W' D + W D') (h.h) - 3 W D (h.h'),   D' = det(H, H', H''').
// W^2 > 0 and |h| > 0 on a regular curve without a pole, so
// sign(dkappa/ds) = sign(lambda) and sign(kappa) = sign(W) sign(D), W's sign
// being constant on the segment (H -> -H, the same curve, keeps lambda and
// negates D). Algorithm 1 runs on lambda's coefficients xi,
// Algorithm 2 on D's (they play eta's role). For W = 1, D = eta, h = C' and
// lambda is the polynomial lambda of lambda.hpp.
//
// Degrees. D is the Wronskian of the three polynomials X, Y, W and h the
// Wronskians of (W, X) and (W, Y); the Wronskian of k polynomials of degree
// <= n has degree <= k (n - k + 1) (its top coefficients cancel: it is
// invariant, up to the factor t^(k(n-k+1)), under t -> 1/t with the
// polynomials reversed). So D, nominally of degree 3n-3, has degree 3n-6 (a
// constant for conics, n = 2), and h, nominally 2n-1, has degree 2n-2. With
// leading terms W ~ w t^n, D ~ c t^(3n-6), h ~ e t^(2n-2):
//   (3 W' D + W D') (h.h) ~ (3n + 3n - 6) w c |e|^2 t^(8n-11)
//   3 W D (h.h')          ~ 3 (2n - 2)    w c |e|^2 t^(8n-11),
// equal, so lambda has degree 8n-12 (4 for conics, 12 for cubics).
//
// Computation, in Bernstein form only (products, derivatives and the exact
// degree reduction bernstein_reduce of bernstein.hpp; the power basis loses
// everything to cancellation): D = X (Y' W'' - W' Y'') - Y (X' W'' - W' X'')
// + W (X' Y'' - Y' X'') at nominal degree 3n-3, reduced three times to 3n-6;
// h at 2n-1, reduced once to 2n-2; lambda at 8n-11, reduced once to 8n-12.
// Every formula is exact for exact inputs, so with T = Rational the result is
// exact (bernstein_reduce checks its precondition there) and with T = Bounded
// each coefficient carries a rigorous error bound.
#include <array>
#include <vector>

#include "numeric/bernstein.hpp"
#include "spline/vec2.hpp"

namespace cmr {

/// The coordinate polynomials X, Y, W of a homogeneous Bezier segment.
template <class T>
struct HomogeneousBezier {
  Bernstein<T> x, y, w;
};

template <class T>
HomogeneousBezier<T> homogeneous_components(const std::vector<HPoint<T>>& H) {
  HomogeneousBezier<T> c;
  for (const HPoint<T>& p : H) {
    c.x.push_back(p.x);
    c.y.push_back(p.y);
    c.w.push_back(p.z);
  }
  return c;
}

namespace rational_detail {

/// a + s b (either may be the empty, zero polynomial; equal degrees otherwise).
template <class T>
Bernstein<T> add(const Bernstein<T>& a, const Bernstein<T>& b, const T& s) {
  if (b.empty()) return a;
  if (a.empty()) {
    Bernstein<T> r(b.size());
    for (std::size_t k = 0; k < b.size(); ++k) r[k] = s * b[k];
    return r;
  }
  CMR_CHECK(a.size() == b.size());
  Bernstein<T> r(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) r[k] = a[k] + s * b[k];
  return r;
}

/// The 2x2 minor u1 v2 - u2 v1 of Bernstein polynomials.
template <class T>
Bernstein<T> minor(const Bernstein<T>& u1, const Bernstein<T>& v2, const Bernstein<T>& u2, const Bernstein<T>& v1) {
  return add(bernstein_product(u1, v2), bernstein_product(u2, v1), T(-1));
}

/// Reduces `times` times; the zero polynomial stays empty.
template <class T>
Bernstein<T> reduce(Bernstein<T> c, int times) {
  for (int i = 0; i < times && !c.empty(); ++i) c = bernstein_reduce(c);
  return c;
}

}  // namespace rational_detail

/// D = det(H, H', H'') at degree 3n-6 (n >= 2).
template <class T>
Bernstein<T> rational_d_bernstein(const HomogeneousBezier<T>& H) {
  using namespace rational_detail;
  const Bernstein<T> x1 = bernstein_derivative(H.x), y1 = bernstein_derivative(H.y), w1 = bernstein_derivative(H.w);
  const Bernstein<T> x2 = bernstein_derivative(x1), y2 = bernstein_derivative(y1), w2 = bernstein_derivative(w1);
  // Cofactors along the first column (X, Y, W) of the 3x3 matrix [H H' H''].
  const Bernstein<T> cx = minor(y1, w2, w1, y2);  // Y' W'' - W' Y''
  const Bernstein<T> cy = minor(x1, w2, w1, x2);  // X' W'' - W' X''
  const Bernstein<T> cw = minor(x1, y2, y1, x2);  // X' Y'' - Y' X''
  Bernstein<T> d = add(add(bernstein_product(H.x, cx), bernstein_product(H.y, cy), T(-1)),
                       bernstein_product(H.w, cw), T(1));
  return reduce(std::move(d), 3);
}

/// h = W X' - W' X (two components) at degree 2n-2.
template <class T>
std::array<Bernstein<T>, 2> rational_h_bernstein(const HomogeneousBezier<T>& H) {
  using namespace rational_detail;
  const Bernstein<T> w1 = bernstein_derivative(H.w);
  return {reduce(minor(H.w, bernstein_derivative(H.x), w1, H.x), 1),
          reduce(minor(H.w, bernstein_derivative(H.y), w1, H.y), 1)};
}

/// xi_0..xi_{8n-12}: lambda = (3 W' D + W D') (h.h) - 3 W D (h.h') in
/// Bernstein form (see the derivation above).
template <class T>
Bernstein<T> rational_lambda_bernstein(const HomogeneousBezier<T>& H) {
  using namespace rational_detail;
  const Bernstein<T> D = rational_d_bernstein(H);
  const auto h = rational_h_bernstein(H);
  const Bernstein<T> hx1 = bernstein_derivative(h[0]), hy1 = bernstein_derivative(h[1]);
  const Bernstein<T> hh = add(bernstein_product(h[0], h[0]), bernstein_product(h[1], h[1]), T(1));
  const Bernstein<T> hh1 = add(bernstein_product(h[0], hx1), bernstein_product(h[1], hy1), T(1));
  const Bernstein<T> a =
      add(bernstein_product(bernstein_derivative(H.w), D), bernstein_product(H.w, bernstein_derivative(D)), Scalar<T>::ratio(1, 3));
  // lambda = 3 [ (W' D + W D' / 3) (h.h) - W D (h.h') ]
  Bernstein<T> lambda = add(bernstein_product(a, hh), bernstein_product(bernstein_product(H.w, D), hh1), T(-1));
  for (T& c : lambda) c = T(3) * c;
  const int n = static_cast<int>(H.w.size()) - 1;
  if (lambda.empty()) return Bernstein<T>(8 * n - 11, T(0));  // D == 0: a straight segment, lambda == 0
  return reduce(std::move(lambda), 1);
}

/// h.h at degree 4n-4: zero exactly where the rational curve's tangent is
/// (p' = h / W^2 with W != 0). The zero polynomial as 4n-3 zero coefficients.
template <class T>
Bernstein<T> rational_speed2_bernstein(const std::vector<HPoint<T>>& points) {
  using namespace rational_detail;
  const auto h = rational_h_bernstein(homogeneous_components<T>(points));
  const Bernstein<T> hh = add(bernstein_product(h[0], h[0]), bernstein_product(h[1], h[1]), T(1));
  const int n = static_cast<int>(points.size()) - 1;
  return hh.empty() ? Bernstein<T>(4 * n - 3, T(0)) : hh;
}

/// D at degree 3n-6 from homogeneous Bezier points.
template <class T>
Bernstein<T> rational_d_bernstein(const std::vector<HPoint<T>>& H) {
  return rational_d_bernstein<T>(homogeneous_components<T>(H));
}
/// lambda at degree 8n-12 from homogeneous Bezier points.
template <class T>
Bernstein<T> rational_lambda_bernstein(const std::vector<HPoint<T>>& H) {
  return rational_lambda_bernstein<T>(homogeneous_components<T>(H));
}

}  // namespace cmr
