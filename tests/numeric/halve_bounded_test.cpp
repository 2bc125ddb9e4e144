// halve_bounded_rows (numeric/halve_bounded.hpp) against
// bernstein_halve<Bounded> with HalfMean: the block proofs' bounds are
// derived for the latter's arithmetic, so values and bounds must agree bit
// for bit, exact zeros (value and bound 0) included.
#include "numeric/halve_bounded.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "numeric/bernstein.hpp"
#include "numeric/scalar.hpp"

namespace cmr {
namespace {

TEST(HalveBounded, BitIdenticalToBernsteinHalve) {
  std::mt19937_64 rng(0x4A1FB0);
  std::uniform_real_distribution<double> mant(-1, 1);
  std::uniform_int_distribution<int> expo(-60, 60);
  for (int n = 1; n <= 34; ++n)
    for (int trial = 0; trial < 100; ++trial) {
      std::vector<Bounded> c(n);
      for (int k = 0; k < n; ++k) {
        const int kind = (trial + k) % 7;
        // Exact zeros, cancelling pairs, and mixed magnitudes.
        if (kind == 0) c[k] = Bounded(0.0, 0.0);
        else if (kind == 1 && k > 0) c[k] = Bounded(-c[k - 1].v, 0.0);
        else c[k] = Bounded(std::ldexp(mant(rng), expo(rng) / (trial % 3 == 0 ? 1 : 20)),
                            trial % 4 == 0 ? 0.0 : std::ldexp(std::fabs(mant(rng)), -50));
      }
      std::vector<Bounded> left(n), right(n), work(n);
      bernstein_halve(c.data(), n, left.data(), right.data(), work.data(), HalfMean{});
      std::vector<double> v(n), e(n), rv(n), re(n), wv(n), we(n);
      for (int k = 0; k < n; ++k) {
        v[k] = c[k].v;
        e[k] = c[k].e;
      }
      halve_bounded_rows(v.data(), e.data(), n, rv.data(), re.data(), wv.data(), we.data());
      for (int k = 0; k < n; ++k) {
        ASSERT_EQ(std::bit_cast<std::uint64_t>(v[k]), std::bit_cast<std::uint64_t>(left[k].v)) << "n " << n << " trial " << trial << " left value " << k;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(e[k]), std::bit_cast<std::uint64_t>(left[k].e)) << "n " << n << " trial " << trial << " left bound " << k;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(rv[k]), std::bit_cast<std::uint64_t>(right[k].v)) << "n " << n << " trial " << trial << " right value " << k;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(re[k]), std::bit_cast<std::uint64_t>(right[k].e)) << "n " << n << " trial " << trial << " right bound " << k;
      }
    }
}

}  // namespace
}  // namespace cmr
