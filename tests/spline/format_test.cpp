// format_number (spline/format.hpp) writes what std::ostream's default float
// field writes with that precision: the form cmr's messages had before it
// used std::to_chars, on seeded doubles of every magnitude, integers, halves,
// signed zeros, infinities and NaN, at precisions 1..17.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

#include "spline/format.hpp"

namespace cmr {
namespace {

std::string streamed(double v, int precision) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

TEST(FormatNumber, WritesWhatTheStreamWrites) {
  std::vector<double> values = {0.0, -0.0, 1.0, -1.0, 3.0, 0.5, 2.5, 1e-9, 0.0478, 123456789.0, 1e21, 1e-300,
                                4.9e-324, std::numeric_limits<double>::max(), std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity(), 0.1, 1.0 / 3.0, 999999.5, 9.9999995e-5};
  std::mt19937_64 rng(24);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-40, 40);
  for (int i = 0; i < 20000; ++i) values.push_back(std::ldexp(mantissa(rng), exponent(rng)));
  for (int i = -2000; i <= 2000; ++i) values.push_back(i / 8.0);
  for (const double v : values)
    for (int p = 1; p <= 17; ++p) ASSERT_EQ(format_number(v, p), streamed(v, p)) << "precision " << p;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int p : {1, 6, 17}) {
    EXPECT_EQ(format_number(nan, p), streamed(nan, p));
    EXPECT_EQ(format_number(-nan, p), streamed(-nan, p));
  }
  EXPECT_EQ(format_number(0.047812345), "0.0478123");
  EXPECT_EQ(format_number(1e-9), "1e-09");
  EXPECT_EQ(format_number(3.0), "3");
}

}  // namespace
}  // namespace cmr
