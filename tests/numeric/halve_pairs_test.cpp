// halve_in_pairs (numeric/halve_pairs.hpp) against bernstein_halve with
// HalfMean: the per-pixel traversal's error bound is derived for the latter's
// arithmetic, so the halves must agree bit for bit, not just closely.
#include "numeric/halve_pairs.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "numeric/bernstein.hpp"

namespace cmr {
namespace {

template <int N>
void expect_bit_identical(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-60, 60);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> c(N);
    // Mixed magnitudes, so that the sums round (a common exponent would
    // make many of them exact and hide a different operation order).
    for (double& x : c) x = std::ldexp(mantissa(rng), exponent(rng) / (trial % 3 == 0 ? 1 : 20));
    std::vector<double> left(N), right(N), work(N);
    bernstein_halve(c.data(), N, left.data(), right.data(), work.data(), HalfMean{});
    std::vector<double> cur = c, pair_right(N);
    halve_in_pairs<N>(cur.data(), pair_right.data());
    for (int i = 0; i < N; ++i) {
      ASSERT_EQ(std::bit_cast<std::uint64_t>(cur[i]), std::bit_cast<std::uint64_t>(left[i]))
          << "N = " << N << ", left " << i << ", trial " << trial;
      ASSERT_EQ(std::bit_cast<std::uint64_t>(pair_right[i]), std::bit_cast<std::uint64_t>(right[i]))
          << "N = " << N << ", right " << i << ", trial " << trial;
    }
  }
}

template <int... Ns>
void expect_all(std::mt19937_64& rng, std::integer_sequence<int, Ns...>) {
  (expect_bit_identical<Ns + 1>(rng), ...);
}

TEST(HalvePairs, BitIdenticalToBernsteinHalve) {
  std::mt19937_64 rng(23);
  expect_all(rng, std::make_integer_sequence<int, 34>{});  // N = 1..34: even and odd, past degree 9's 30
}

TEST(HalvePairs, HalvesMeetAtTheMidpointValue) {
  // Independent of bernstein_halve: both halves' shared end is the value at
  // t = 1/2, sum_i C(n, i) c_i / 2^n (exact here: small integers).
  double c[7] = {3, -1, 4, 1, -5, 9, 2}, right[7];
  double mid = 0, binom = 1;
  for (int i = 0; i < 7; ++i) {
    mid += binom * c[i];
    binom = binom * (6 - i) / (i + 1);
  }
  mid /= 64;
  halve_in_pairs<7>(c, right);
  EXPECT_EQ(c[6], mid);
  EXPECT_EQ(right[0], mid);
  EXPECT_EQ(c[0], 3);
  EXPECT_EQ(right[6], 2);
}

}  // namespace
}  // namespace cmr
