// The editor's embedded example splines equal their files, so an installed
// cmr (which reads no source tree) benchmarks the very spline the docs name.
#include <gtest/gtest.h>

#include "spline/spline_json.hpp"
#include "tools/edit/examples.hpp"

namespace cmr::edit {
namespace {

TEST(EditExamples, EmbeddedFig8EqualsTheExampleFile) {
  const BSpline file = read_spline_file(std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8.json");
  const BSpline embedded = fig8_spline();
  EXPECT_EQ(embedded.name(), file.name());
  EXPECT_EQ(embedded.degree(), file.degree());
  EXPECT_EQ(embedded.knots(), file.knots());
  ASSERT_EQ(embedded.points().size(), file.points().size());
  for (std::size_t i = 0; i < file.points().size(); ++i) {
    EXPECT_EQ(embedded.points()[i].x, file.points()[i].x) << "point " << i;
    EXPECT_EQ(embedded.points()[i].y, file.points()[i].y) << "point " << i;
  }
  EXPECT_EQ(embedded.weights(), file.weights());
}

}  // namespace
}  // namespace cmr::edit
