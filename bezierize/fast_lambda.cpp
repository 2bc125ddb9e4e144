#include "bezierize/fast_lambda.hpp"

#include <utility>

#include "spline/errors.hpp"

namespace cmr {
namespace {

constexpr double cbinom(int n, int k) {
  if (k < 0 || k > n) return 0;
  double r = 1;  // exact: every intermediate C(n-k+i, i) is an integer below 2^53 for n <= 60
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

// Weight tables for degree N, computed at compile time (each a binomial
// ratio rounded once, as Scalar<double>::ratio does).
template <int N>
struct Tables {
  static constexpr int m = N - 1;
  static constexpr int n_nu = 2 * m - 1, n_g = 2 * m + 1, n_xi = 4 * m - 2;
  std::array<double, (m + 1) * (m + 1)> eta{}, g{};
  std::array<double, (4 * m - 2) * (2 * m + 1)> pa{}, pb{};  // [k][i]
  constexpr Tables() {
    for (int i = 0; i <= m; ++i)
      for (int j = 0; j <= m; ++j) {
        if (j > i) eta[i * (m + 1) + j] = (j - i) * cbinom(m, i) * cbinom(m, j) / cbinom(2 * m - 2, i + j - 1);
        if (j >= i) g[i * (m + 1) + j] = (i == j ? 1 : 2) * cbinom(m, i) * cbinom(m, j) / cbinom(2 * m, i + j);
      }
    const int A = 2 * m - 3, B = 2 * m, C = 2 * m - 2, D = 2 * m - 1;
    for (int k = 0; k < n_xi; ++k)
      for (int i = 0; i <= 2 * m; ++i) {
        if (m >= 2 && i <= A && k - i >= 0 && k - i <= B) pa[k * (2 * m + 1) + i] = cbinom(A, i) * cbinom(B, k - i) / cbinom(A + B, k);
        if (i <= C && k - i >= 0 && k - i <= D) pb[k * (2 * m + 1) + i] = cbinom(C, i) * cbinom(D, k - i) / cbinom(C + D, k);
      }
  }
};

// The abs-formula of the error bound is monotone in |q|, so evaluating it
// once with every |q| = 1 (S_k) and scaling by M^4 (xi is quartic in q) or
// M^2 (eta is quadratic), M = the largest |coordinate| of the abs-hodograph,
// bounds E_abs for every input at the cost of one maximum.
template <int N>
struct Scales {
  std::array<double, 4 * N - 6> xi{};
  std::array<double, 2 * N - 3> nu{};
  constexpr Scales() {
    constexpr Tables<N> t;
    constexpr int m = N - 1, n_nu = 2 * m - 1, n_g = 2 * m + 1;
    double nua[n_nu] = {}, ga[n_g] = {};
    for (int i = 0; i <= m; ++i)
      for (int j = 0; j <= m; ++j) {
        if (j > i) nua[i + j - 1] += t.eta[i * (m + 1) + j] * 2;
        if (j >= i) ga[i + j] += t.g[i * (m + 1) + j] * 2;
      }
    for (int k = 0; k < n_nu; ++k) nu[k] = nua[k];
    const int A = 2 * m - 3, B = 2 * m, C = 2 * m - 2, D = 2 * m - 1;
    for (int k = 0; k < 4 * m - 2; ++k) {
      double a = 0, b = 0;
      for (int i = 0; i <= 2 * m; ++i) {
        if (m >= 2 && i <= A && k - i >= 0 && k - i <= B)
          a += t.pa[k * (2 * m + 1) + i] * ((n_nu - 1) * (nua[i + 1] + nua[i]) * ga[k - i]);
        if (i <= C && k - i >= 0 && k - i <= D)
          b += t.pb[k * (2 * m + 1) + i] * (nua[i] * (n_g - 1) * (ga[k - i + 1] + ga[k - i]));
      }
      xi[k] = a + 1.5 * b;
    }
  }
};

template <int N>
void lambda_eta(const Vec2* P, FastCoefficients& out) {
  static constexpr Tables<N> t;
  static constexpr Scales<N> scale;
  constexpr int m = N - 1, n_nu = Tables<N>::n_nu, n_g = Tables<N>::n_g, n_xi = Tables<N>::n_xi;
  double qx[N], qy[N];
  double M = 0;
  _Pragma("GCC unroll 64")
  for (int i = 0; i < N; ++i) {
    qx[i] = N * (P[i + 1].x - P[i].x);
    qy[i] = N * (P[i + 1].y - P[i].y);
    M = std::max({M, std::fabs(P[i + 1].x) + std::fabs(P[i].x), std::fabs(P[i + 1].y) + std::fabs(P[i].y)});
  }
  M *= N;
  double nu[n_nu] = {}, g[n_g] = {};
  _Pragma("GCC unroll 64")
  for (int i = 0; i <= m; ++i)
    _Pragma("GCC unroll 64")
    for (int j = i + 1; j <= m; ++j) nu[i + j - 1] += t.eta[i * (m + 1) + j] * (qx[i] * qy[j] - qy[i] * qx[j]);
  _Pragma("GCC unroll 64")
  for (int i = 0; i <= m; ++i)
    _Pragma("GCC unroll 64")
    for (int j = i; j <= m; ++j) g[i + j] += t.g[i * (m + 1) + j] * (qx[i] * qx[j] + qy[i] * qy[j]);
  double dn[n_nu] = {}, dg[n_g] = {};
  _Pragma("GCC unroll 64")
  for (int i = 0; i + 1 < n_nu; ++i) dn[i] = (n_nu - 1) * (nu[i + 1] - nu[i]);
  _Pragma("GCC unroll 64")
  for (int i = 0; i + 1 < n_g; ++i) dg[i] = (n_g - 1) * (g[i + 1] - g[i]);
  constexpr int A = 2 * m - 3, B = 2 * m, C = 2 * m - 2, D = 2 * m - 1;  // degrees of eta', g, eta, g'
  _Pragma("GCC unroll 64")
  for (int k = 0; k < n_xi; ++k) {
    double a = 0, b = 0;
    if constexpr (m >= 2) {
      _Pragma("GCC unroll 64")
      for (int i = 0; i <= A; ++i)
        if (k - i >= 0 && k - i <= B) a += t.pa[k * (2 * m + 1) + i] * (dn[i] * g[k - i]);
    }
    _Pragma("GCC unroll 64")
    for (int i = 0; i <= C; ++i)
      if (k - i >= 0 && k - i <= D) b += t.pb[k * (2 * m + 1) + i] * (nu[i] * dg[k - i]);
    out.xi[k] = a - 1.5 * b;
  }
  const double unit = 0.5 * Bounded::kRound;  // u
  const double M2 = M * M, M4 = M2 * M2;
  // (1 + 2^-20) covers the rounding of M^4 and of the scale constants.
  const double xs = (3 * m + 20) * unit * M4 * (1 + 0x1p-20), ns = (m + 12) * unit * M2 * (1 + 0x1p-20);
  _Pragma("GCC unroll 64")
  for (int k = 0; k < n_xi; ++k) out.xi_err[k] = xs * scale.xi[k] + 64 * Bounded::kTiny;
  _Pragma("GCC unroll 64")
  for (int k = 0; k < n_nu; ++k) {
    out.nu[k] = nu[k];
    out.nu_err[k] = ns * scale.nu[k] + 16 * Bounded::kTiny;
  }
  out.n_xi = n_xi;
  out.n_nu = n_nu;
}

template <int... Ns>
void dispatch(const Vec2* P, int n, FastCoefficients& out, std::integer_sequence<int, Ns...>) {
  ((n == Ns + 2 ? lambda_eta<Ns + 2>(P, out) : void()), ...);
}

}  // namespace

void fast_lambda_eta(const Vec2* P, int n, FastCoefficients& out) {
  CMR_CHECK(n >= 2 && n <= kFastMaxDegree);
  dispatch(P, n, out, std::make_integer_sequence<int, kFastMaxDegree - 1>{});
}

}  // namespace cmr
