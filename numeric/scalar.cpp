#include "numeric/scalar.hpp"

#include "spline/errors.hpp"

namespace cmr {

namespace {

/// Pascal's triangle up to row kTableRows - 1 (Bernstein products of the
/// degrees cmr uses stay below it): the same integers the loop below
/// computes, looked up instead of divided out on every call.
constexpr int kTableRows = 33;
struct PascalTable {
  Int128 c[kTableRows][kTableRows] = {};
  constexpr PascalTable() {
    for (int n = 0; n < kTableRows; ++n) {
      c[n][0] = c[n][n] = 1;
      for (int k = 1; k < n; ++k) c[n][k] = c[n - 1][k - 1] + c[n - 1][k];
    }
  }
};
constexpr PascalTable kPascal{};  // built by the compiler: no order of initialization to mind

}  // namespace

Int128 binomial(int n, int k) {
  CMR_CHECK(n >= 0 && n <= 120);
  if (k < 0 || k > n) return 0;
  if (n < kTableRows) return kPascal.c[n][k];
  if (k > n - k) k = n - k;
  Int128 r = 1;
  // r = C(n-k+i, i) after step i; each step's division is exact.
  for (int i = 1; i <= k; ++i) r = r * static_cast<Int128>(n - k + i) / static_cast<Int128>(i);
  return r;
}

mpz_class to_mpz(Int128 v) {
  mpz_class hi(static_cast<unsigned long>(static_cast<std::uint64_t>(v >> 64)));
  mpz_class lo(static_cast<unsigned long>(static_cast<std::uint64_t>(v)));
  return mpz_class((hi << 64) + lo);
}

}  // namespace cmr
