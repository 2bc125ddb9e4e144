// Why a region is empty or full (region/region_reason.hpp): the support of
// the moved point, the judged segments outside it that fail whatever it
// does, and the closed curve's support range.
#include "region/region_reason.hpp"

#include <gtest/gtest.h>

#include "spline/fields.hpp"

namespace cmr {
namespace {

// examples/figures/fig8.json: segments 0 and 1 are not monotone, 2 is.
BSpline fig8() {
  return BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7},
                       {{1.30, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95}, {-6.78, -9.78}});
}

RegionResult render(const RegionProblem& p) { return CpuRegionBackend(1).render(p); }

RegionRequest request(int k, std::optional<SegmentRange> range = {}) {
  RegionRequest o;
  o.point = k;
  o.segments = range;
  o.width = o.height = 24;
  o.depth = false;
  return o;
}

TEST(RegionReason, SupportOutsideTheJudgedSegments) {
  const RegionProblem p = RegionProblem::make(fig8(), request(0, SegmentRange{2, 2}));
  EXPECT_TRUE(acted_segments(p).empty());
  const auto why = region_reason(p, render(p));
  ASSERT_TRUE(why.has_value());
  EXPECT_EQ(*why, "P0 does not act on segment 2: every position gives the same answer (the region is all or nothing)");
}

TEST(RegionReason, FixedFailingSegmentsAreNamed) {
  const RegionProblem p = RegionProblem::make(fig8(), request(5));
  EXPECT_EQ(acted_segments(p), (std::vector<int>{2}));
  EXPECT_EQ(fixed_failing_segments(p), (std::vector<int>{0, 1}));
  const auto why = region_reason(p, render(p));
  ASSERT_TRUE(why.has_value());
  EXPECT_EQ(*why, "segments 0..1 are non-monotone whatever P5 does (P5 acts on segment 2)");
  // P3 acts on every segment: its region is neither empty nor full here.
  const RegionProblem q = RegionProblem::make(fig8(), request(3));
  EXPECT_TRUE(fixed_failing_segments(q).empty());
  EXPECT_FALSE(region_reason(q, render(q)).has_value());
}

TEST(RegionReason, ClosedSupportRange) {
  const BSpline loop = BSpline::make_closed(
      2, {0, 1, 2, 3, 4, 5, 6}, {{1, 0}, {0.4, 0.9}, {-0.6, 0.8}, {-1.1, -0.1}, {-0.3, -1}, {0.7, -0.8}});
  EXPECT_EQ(closed_support_range(loop, 2), (SegmentRange{0, 2}));
  EXPECT_EQ(closed_support_range(loop, 4), (SegmentRange{2, 4}));
  EXPECT_FALSE(closed_support_range(loop, 0).has_value());  // segments 4, 5, 0: across the seam
  EXPECT_FALSE(closed_support_range(fig8(), 2).has_value());  // open
  // Judged over the whole period, a closed curve's region is empty, and the
  // reason says so with the support to judge instead.
  const RegionProblem p = RegionProblem::make(loop, request(2));
  const auto why = region_reason(p, render(p));
  ASSERT_TRUE(why.has_value());
  EXPECT_NE(why->find("never monotone over its whole period"), std::string::npos) << *why;
  // segments: the field (spline/fields.hpp), which the cmr command shows as its flag.
  EXPECT_NE(plain_fields(*why).find("segments 0..2"), std::string::npos) << *why;
  EXPECT_EQ(segment_list_text({1, 3, 4}), "segments 1, 3, 4");
}

}  // namespace
}  // namespace cmr
