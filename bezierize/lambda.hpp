#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
// eta and lambda of a planar Bezier segment in Bernstein form (CAD&A 2024 §3).
//
// Let P(t) = sum_i B_i^n P_i, Q = P' the hodograph: degree m = n-1 with
// points q_i = n (P_{i+1} - P_i).
//
// eta(t) = det(P', P'') = det(Q, Q'), the numerator of the curvature, has
// degree 2n-4 (the leading terms of Q and Q' are parallel). Writing
// det(Q, Q') = sum_{i<j} det(q_i, q_j) W(B_i^m, B_j^m) with the Wronskian
// W = B_i^m B_j^m' - B_j^m B_i^m' = (j-i) B_i^m B_j^m / (t (1-t)) gives, exactly
// at degree 2m-2 = 2n-4,
//     nu_k = sum_{i<j, i+j-1=k} (j-i) C(m,i) C(m,j) / C(2m-2,k) det(q_i, q_j).
//
// g(t) = Q.Q at degree 2m: g_k = sum_{i+j=k} C(m,i) C(m,j)/C(2m,k) q_i.q_j.
//
// lambda(t) = det(P',P''') g - 3 eta (P'.P'') = eta' g - (3/2) eta g', the
// numerator of dkappa/ds: eta' (degree 2n-5) times g (2n-2) and eta (2n-4)
// times g' (2n-3) are both of degree exactly 4n-7, so the Bernstein
// coefficients xi_0..xi_{4n-7} come out at that degree with no reduction.
// (n = 2: eta is a constant, eta' = 0 and lambda = -(3/2) eta g', degree 1.)
#include <vector>

#include "numeric/bernstein.hpp"
#include "spline/vec2.hpp"

namespace cmr {

/// q_i = n (P_{i+1} - P_i).
template <class T>
std::vector<Point<T>> hodograph(const std::vector<Point<T>>& P) {
  const int n = static_cast<int>(P.size()) - 1;
  std::vector<Point<T>> q;
  q.reserve(n);
  for (int i = 0; i < n; ++i) q.push_back(T(n) * (P[i + 1] - P[i]));
  return q;
}

/// nu_0..nu_{2n-4}: eta = det(P', P'') in Bernstein form.
template <class T>
Bernstein<T> eta_bernstein(const std::vector<Point<T>>& P) {
  const std::vector<Point<T>> q = hodograph<T>(P);
  const int m = static_cast<int>(q.size()) - 1;
  Bernstein<T> nu(2 * m - 1, T(0));
  for (int i = 0; i <= m; ++i)
    for (int j = i + 1; j <= m; ++j) {
      const int k = i + j - 1;
      const Int128 num = static_cast<Int128>(j - i) * binomial(m, i) * binomial(m, j);
      nu[k] += Scalar<T>::ratio(num, binomial(2 * m - 2, k)) * det(q[i], q[j]);
    }
  return nu;
}

/// g = P'.P' in Bernstein form, degree 2n-2.
template <class T>
Bernstein<T> speed2_bernstein(const std::vector<Point<T>>& P) {
  const std::vector<Point<T>> q = hodograph<T>(P);
  const int m = static_cast<int>(q.size()) - 1;
  Bernstein<T> g(2 * m + 1, T(0));
  for (int i = 0; i <= m; ++i)
    for (int j = i; j <= m; ++j) {
      const int k = i + j;
      const Int128 num = (i == j ? 1 : 2) * binomial(m, i) * binomial(m, j);
      g[k] += Scalar<T>::ratio(num, binomial(2 * m, k)) * dot(q[i], q[j]);
    }
  return g;
}

/// xi_0..xi_{4n-7}: lambda in Bernstein form.
template <class T>
Bernstein<T> lambda_bernstein(const std::vector<Point<T>>& P) {
  const Bernstein<T> eta = eta_bernstein<T>(P);
  const Bernstein<T> g = speed2_bernstein<T>(P);
  const Bernstein<T> a = bernstein_product(bernstein_derivative(eta), g);
  const Bernstein<T> b = bernstein_product(eta, bernstein_derivative(g));
  Bernstein<T> xi(b.size(), T(0));
  const T three_halves = Scalar<T>::ratio(3, 2);
  for (std::size_t k = 0; k < xi.size(); ++k) xi[k] = (a.empty() ? T(0) : a[k]) - three_halves * b[k];
  return xi;
}

}  // namespace cmr
