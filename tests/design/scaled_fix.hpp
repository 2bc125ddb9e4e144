#pragma once
// A fix of a curve far from unit size against its copy's (fix() and
// space_fix() search such a curve as its copy scaled by a power of two, and
// scale the answer back): the same moves, times 2^k bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace cmr::test {

/// `far`: the fix of the curve; `near`: of its copy, the curve times 2^-k.
template <class Result>
void expect_copy_scaled_back(const Result& far, const Result& near, int k, const std::string& what) {
  ASSERT_TRUE(near.fixed) << what << ", the copy: " << near.reason;
  ASSERT_TRUE(far.fixed) << what << ": " << far.reason;
  ASSERT_EQ(far.moves.size(), near.moves.size()) << what;
  for (std::size_t i = 0; i < far.moves.size(); ++i) {
    EXPECT_EQ(far.moves[i].point, near.moves[i].point) << what;
    EXPECT_EQ(far.moves[i].to, std::ldexp(1.0, k) * near.moves[i].to) << what;
    EXPECT_EQ(far.moves[i].distance, std::ldexp(near.moves[i].distance, k)) << what;
  }
  EXPECT_EQ(far.size, std::ldexp(near.size, k)) << what;
  EXPECT_EQ(far.total_squared, std::ldexp(near.total_squared, 2 * k)) << what;
  EXPECT_TRUE(far.certificate_holds) << what;
}

}  // namespace cmr::test
