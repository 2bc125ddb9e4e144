// A cmr built without OpenCASCADE (step/step_absent.cpp): STEP input is an
// InputError (exit 2) that names the file and says why, in one line.
#include <gtest/gtest.h>

#include "spline/errors.hpp"
#include "step/step.hpp"

TEST(StepAbsent, ReadingSaysBuiltWithoutStepSupport) {
  EXPECT_FALSE(cmr::import::step_supported());
  try {
    cmr::import::read_step_curves("part.step");
    FAIL() << "no InputError";
  } catch (const cmr::InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("part.step: cmr was built without STEP support", 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(StepAbsent, CurveJsonHasWeightsOnlyWhenRational) {
  cmr::import::StepCurve c;
  c.name = "edge 1";
  c.degree = 2;
  c.knots = {0, 0, 1, 1};
  c.points = {{0, 0, 0}, {1, 1, 0}, {2, 0, 1}};
  EXPECT_FALSE(cmr::import::step_curve_json(c).contains("weights"));
  EXPECT_FALSE(cmr::import::step_curve_json(c).contains("closed"));
  c.weights = {1, 0.5, 1};
  EXPECT_EQ(cmr::import::step_curve_json(c)["weights"], nlohmann::ordered_json({1, 0.5, 1}));
  EXPECT_EQ(cmr::import::step_curve_json(c)["points"][2], nlohmann::ordered_json({2, 0, 1}));
}

// The pre-scan that keeps deep nesting away from OpenCASCADE (issue 42 E4):
// parentheses inside 'strings' ('' is a quote) and /* comments */ do not count.
TEST(StepPrescan, CountsParenthesesOutsideStringsAndComments) {
  using cmr::import::step_nesting;
  EXPECT_EQ(step_nesting("").depth, 0);
  EXPECT_EQ(step_nesting("#1=CARTESIAN_POINT('',(0.,0.,0.));").depth, 2);
  const auto n = step_nesting("#1=A((1));\n#2=B('((((it''s ((',/* ((((( */\n(((2))));");
  EXPECT_EQ(n.depth, 4);
  EXPECT_EQ(n.line, 3);
  const std::string deep = "#1=CARTESIAN_POINT(''," + std::string(200000, '(') + "0." + std::string(200000, ')') + ");";
  EXPECT_EQ(step_nesting(deep).depth, 200001);
  // An unclosed string or comment ends the scan (OCCT refuses the file).
  EXPECT_EQ(step_nesting("#1=A((' (((((").depth, 2);
  EXPECT_EQ(step_nesting("#1=A(( /* (((((").depth, 2);
}
