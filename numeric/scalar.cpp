#include "numeric/scalar.hpp"

#include "spline/errors.hpp"

namespace cmr {

Int128 binomial(int n, int k) {
  CMR_CHECK(n >= 0 && n <= 120);
  if (k < 0 || k > n) return 0;
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
