#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.
// Bernstein-form polynomials on [0, 1]: p(t) = sum_i c_i B_i^n(t),
// B_i^n = C(n,i) t^i (1-t)^{n-i}. Generic over the scalar type (scalar.hpp).
#include <vector>

#include "numeric/scalar.hpp"
#include "spline/errors.hpp"

namespace cmr {

template <class T>
using Bernstein = std::vector<T>;  ///< coefficients c_0..c_n; degree = size-1

/// p(t) by de Casteljau.
template <class T>
T bernstein_eval(Bernstein<T> c, const T& t) {
  CMR_CHECK(!c.empty());
  const T s = T(1) - t;
  for (std::size_t r = 1; r < c.size(); ++r)
    for (std::size_t i = 0; i + r < c.size(); ++i) c[i] = s * c[i] + t * c[i + 1];
  return c[0];
}

/// p'(t) in Bernstein form of degree n-1: n (c_{i+1} - c_i). A constant's
/// derivative is the empty polynomial (identically zero, no coefficients).
template <class T>
Bernstein<T> bernstein_derivative(const Bernstein<T>& c) {
  const int n = static_cast<int>(c.size()) - 1;
  Bernstein<T> d;
  d.reserve(n > 0 ? n : 0);
  for (int i = 0; i < n; ++i) d.push_back(T(n) * (c[i + 1] - c[i]));
  return d;
}

/// The sign of p on all of [0, 1] when every coefficient is certainly of that
/// one sign (+1 or -1): p is then a convex combination of values of that sign
/// and has no root in [0, 1]. 0 when that is not certain (with T = Bounded, a
/// coefficient whose bound straddles 0; with Rational, a zero or a change).
template <class T>
int strict_sign(const Bernstein<T>& p) {
  if (p.empty()) return 0;
  const int s = Scalar<T>::sign(p.front());
  if (s != 1 && s != -1) return 0;
  for (const T& c : p)
    if (Scalar<T>::sign(c) != s) return 0;
  return s;
}

/// (p q)(t) at degree m+n: c_k = sum_{i+j=k} C(m,i) C(n,j) / C(m+n,k) a_i b_j.
/// An empty operand (zero polynomial) gives the empty polynomial.
template <class T>
Bernstein<T> bernstein_product(const Bernstein<T>& a, const Bernstein<T>& b) {
  if (a.empty() || b.empty()) return {};
  const int m = static_cast<int>(a.size()) - 1, n = static_cast<int>(b.size()) - 1;
  Bernstein<T> c(m + n + 1, T(0));
  for (int k = 0; k <= m + n; ++k) {
    const Int128 den = binomial(m + n, k);
    for (int i = std::max(0, k - n); i <= std::min(m, k); ++i) {
      c[k] += Scalar<T>::ratio(binomial(m, i) * binomial(n, k - i), den) * (a[i] * b[k - i]);
    }
  }
  return c;
}

/// The same polynomial at degree n+1: c'_i = i/(n+1) c_{i-1} + (1 - i/(n+1)) c_i.
template <class T>
Bernstein<T> bernstein_elevate(const Bernstein<T>& c) {
  const int n = static_cast<int>(c.size()) - 1;
  Bernstein<T> e(n + 2);
  e[0] = c[0];
  e[n + 1] = c[n];
  for (int i = 1; i <= n; ++i)
    e[i] = Scalar<T>::ratio(i, n + 1) * c[i - 1] + Scalar<T>::ratio(n + 1 - i, n + 1) * c[i];
  return e;
}

/// The same polynomial at degree n-1, for a c_0..c_n whose polynomial has
/// degree < n (its leading power coefficient, sum_i (-1)^(n-i) C(n,i) c_i,
/// is 0): the inverse of bernstein_elevate. From c_i = i/n b_{i-1} + (n-i)/n b_i,
///   from the left:  b_0 = c_0,     b_i = (n c_i - i b_{i-1}) / (n-i),
///   from the right: b_{n-1} = c_n, b_{i-1} = (n c_i - (n-i) b_i) / i.
/// Both recurrences are exact when the degree really is below n; b_i is
/// taken from the left for i < n/2 and from the right otherwise (each step
/// then multiplies earlier errors by at most 1). In exact arithmetic
/// (T = Rational) the two sweeps are checked to agree everywhere, which is
/// the precondition. Degree 0 (one coefficient) is the caller's error.
template <class T>
Bernstein<T> bernstein_reduce(const Bernstein<T>& c) {
  const int n = static_cast<int>(c.size()) - 1;
  CMR_CHECK(n >= 1);
  Bernstein<T> left(n), right(n);
  left[0] = c[0];
  for (int i = 1; i < n; ++i) left[i] = Scalar<T>::ratio(n, n - i) * c[i] - Scalar<T>::ratio(i, n - i) * left[i - 1];
  right[n - 1] = c[n];
  for (int i = n - 1; i >= 1; --i) right[i - 1] = Scalar<T>::ratio(n, i) * c[i] - Scalar<T>::ratio(n - i, i) * right[i];
  if constexpr (Scalar<T>::exact) CMR_CHECK(left == right);
  Bernstein<T> b(n);
  for (int i = 0; i < n; ++i) b[i] = 2 * i < n ? left[i] : right[i];
  return b;
}

/// de Casteljau subdivision at t: left covers [0, t], right [t, 1], both
/// reparametrised to [0, 1].
template <class T>
void bernstein_subdivide(const Bernstein<T>& c, const T& t, Bernstein<T>& left, Bernstein<T>& right) {
  const std::size_t n1 = c.size();
  Bernstein<T> w = c;
  left.assign(n1, T(0));
  right.assign(n1, T(0));
  const T s = T(1) - t;
  left[0] = w[0];
  right[n1 - 1] = w[n1 - 1];
  for (std::size_t r = 1; r < n1; ++r) {
    for (std::size_t i = 0; i + r < n1; ++i) w[i] = s * w[i] + t * w[i + 1];
    left[r] = w[0];
    right[n1 - 1 - r] = w[n1 - 1 - r];
  }
}

/// The mean used when halving: Scalar<T>::half(a + b), exact in binary up to
/// the one rounding of the sum (Scalar<T>::half is exact).
struct HalfMean {
  template <class T>
  T operator()(const T& a, const T& b) const {
    return Scalar<T>::half(a + b);
  }
};

/// Subdivision at t = 1/2, the step of Algorithms 1 and 2, and the one
/// halving routine of the project (every traversal and the region piece
/// polynomials use it): de Casteljau with every new coefficient mid(c_i,
/// c_{i+1}) of two. left covers [0, 1/2], right [1/2, 1]; c is copied to
/// work first, so left or right may be c itself.
template <class T, class Mid = HalfMean>
void bernstein_halve(const T* c, std::size_t n1, T* left, T* right, T* work, Mid mid = {}) {
  for (std::size_t i = 0; i < n1; ++i) work[i] = c[i];
  left[0] = work[0];
  right[n1 - 1] = work[n1 - 1];
  for (std::size_t r = 1; r < n1; ++r) {
    for (std::size_t i = 0; i + r < n1; ++i) work[i] = mid(work[i], work[i + 1]);
    left[r] = work[0];
    right[n1 - 1 - r] = work[n1 - 1 - r];
  }
}

}  // namespace cmr
