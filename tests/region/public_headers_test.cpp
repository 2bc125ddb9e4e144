// The headers a library user includes for analysis and regions must not pull
// in the internal scalar types (GMP rationals, __int128): users link
// cmr::bezierize without compiling against GMP's C++ headers.
#include "bezierize/analyze.hpp"
#include "bezierize/classify.hpp"
#include "region/region.hpp"
#include "bezierize/space_analyze.hpp"
#include "region/space_region.hpp"

#include <gtest/gtest.h>

#if defined(CMR_INTERNAL_SCALAR_TYPES)
#error "a public analysis header includes numeric/scalar.hpp (GMP, __int128)"
#endif
#if defined(__GMP_PLUSPLUS__) || defined(__GMP_H__)
#error "a public analysis header includes GMP"
#endif

namespace cmr {
namespace {

TEST(PublicHeaders, AnalysisAndRegionsWithoutInternalScalars) {
  // Compiling this file is the check; use the API once so it is exercised.
  const BSpline s = BSpline::bezier({{0, 0}, {1, 1}, {3, 1}, {4, 0}});
  const SplineAnalysis a = analyze(s);
  EXPECT_EQ(a.segments.size(), 1u);
  RegionRequest r;
  r.width = r.height = 8;
  EXPECT_EQ(RegionProblem::make(s, r).request().width, 8);
}

}  // namespace
}  // namespace cmr
