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
  const auto step_nesting = [](std::string_view t) { return cmr::import::step_scan(t); };
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

// The pre-scan's numbers (issue 42 E5): a real beyond 1e100 in magnitude, a
// real that overflows a double and an integer beyond 32 bits are found, with
// the entity whose parameters hold them; numbers in strings, comments,
// keywords and references are not numbers; underflow is harmless.
TEST(StepPrescan, FindsTheFirstNumberOutOfRangeAndItsEntity) {
  using cmr::import::step_scan;
  const auto ok = step_scan("ISO-10303-21;\nDATA;\n#1=CARTESIAN_POINT('1.E308',(1.E100,-2.5E-3,1.E-400));\n"
                            "#22 = B_SPLINE_CURVE_2('',3,(#1,#99999999999),.F.,.T.);/* 1.E308 */ #3=X(\"1E999\",2147483647);");
  EXPECT_EQ(ok.bad_number, "") << ok.bad_number;
  const auto big = step_scan("DATA;\n#7=A((0.,1.));\n#95 =\n CARTESIAN_POINT('',(1.E308,\n-1.7E308,1.E308));\n#96=B(1.E999);");
  EXPECT_EQ(big.bad_number, "1.E308");
  EXPECT_EQ(big.bad_entity, 95);
  EXPECT_EQ(big.bad_line, 4);
  const auto neg = step_scan("#4=A(2.,-1.7E308);");
  EXPECT_EQ(neg.bad_number, "-1.7E308");
  EXPECT_EQ(neg.bad_entity, 4);
  EXPECT_EQ(step_scan("#5=A(1.0000001E100);").bad_number, "1.0000001E100");
  EXPECT_EQ(step_scan("#6=A(1E400);").bad_number, "1E400");  // overflows a double
  EXPECT_EQ(step_scan("#8=A(2147483648);").bad_number, "2147483648");
  EXPECT_EQ(step_scan("#9=A(-2147483649);").bad_entity, 9);
  EXPECT_EQ(step_scan("HEADER;FOO(3.E200);").bad_entity, 0);  // outside any entity
  // A 40-digit instance name saturates (no overflow) and is still the entity.
  const auto long_id = step_scan("#" + std::string(40, '9') + " = A(1.E300);");
  EXPECT_GE(long_id.bad_entity, 100'000'000'000'000'000LL);
}

// The pre-scan's syntax: an instance's parameters close once, then ';'
// (fuzz_step: OCCT's parser turned "#100 = A(3) B((#1)) C('x') );" into a
// null entity that its model loader dereferenced, SIGSEGV).
TEST(StepPrescan, FindsParenthesesThatDoNotCloseAnInstance) {
  using cmr::import::step_scan;
  EXPECT_EQ(step_scan("ISO-10303-21;\nHEADER;\nFILE_NAME('a;)(',(''));\nENDSEC;\nDATA;\n#1=A((1.,2.),'x');\n"
                      "#2 = ( B(1) C((#1)) ) /* ) */ ;\n#3=D(\n(2));\nENDSEC;\nEND-ISO-10303-21;\n").syntax, "");
  const auto extra = step_scan("DATA;\n#1=A(1);\n#100 = B(3)\n C((#1)) );");
  EXPECT_EQ(extra.syntax, "more after a closed parameter list (expected ';')");
  EXPECT_EQ(extra.syntax_line, 4);
  EXPECT_EQ(step_scan("#1=A(1));").syntax, "a ')' without its '('");
  EXPECT_EQ(step_scan("#1=A((1);\n#2=B(2);").syntax, "a ';' inside parentheses");
  EXPECT_EQ(step_scan("#1=A(1)(2);").syntax, "a '(' after a closed parameter list (expected ';')");
  const auto twice = step_scan("#1=A(1);\n#118 = B(#1);\n#2=C(2);\n#118=D(3);");
  EXPECT_EQ(twice.syntax, "#118 is defined twice (first on line 2)");
  EXPECT_EQ(twice.syntax_line, 4);
}
