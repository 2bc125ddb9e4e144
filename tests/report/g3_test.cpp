// g3-at-smooth-nodes (report/g3.hpp): dkappa/ds and torsion at both sides of
// a joint against exact references from a committed script
// (gen_g3_reference.py, Python fractions: power-series division of the
// homogeneous coordinates, not the C++ Leibniz differences), the gate's
// verdicts (a uniform cubic B-spline, C2 but not G3, fails; a cubic split by
// de Casteljau passes; moving the third point from the joint keeps G2 and
// fails G3; the same in 3D, where torsion changes too; rational pieces), the
// space report and the command line.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "bezierize/space_analyze.hpp"
#include "report/batch.hpp"
#include "report/g3.hpp"
#include "report/report.hpp"
#include "report/space_report.hpp"
#include "spline/errors.hpp"
#include "spline/format.hpp"
#include "tests/cli_util.hpp"
#include "tests/report/g3_reference.hpp"

namespace cmr::report {
namespace {

using reference::G3Reference;

void expect_close(double got, double want, const std::string& what) {
  EXPECT_LE(std::abs(got - want), 1e-12 * std::abs(want)) << what << ": " << got << " vs " << want;
}

ReportOptions gates(const std::string& require) {
  ReportOptions o;
  o.regions = false;
  parse_require_list(require, o);
  return o;
}

BSpline planar(const G3Reference& c) {
  std::vector<Vec2> pts;
  for (const auto& p : c.points) pts.push_back({p[0], p[1]});
  return BSpline::make(c.degree, c.knots, pts, c.name, c.weights);
}

SpaceSpline space(const G3Reference& c, std::array<double, 3> move_last = {0, 0, 0}) {
  std::vector<Vec3> pts;
  for (const auto& p : c.points) pts.push_back({p[0], p[1], p[2]});
  pts.back() += Vec3(move_last[0], move_last[1], move_last[2]);
  return SpaceSpline::make(c.degree, c.knots, pts, c.name, c.weights);
}

/// The joint between the two pieces: segments 0 | 1 (knot 1) or, for the
/// unclamped uniform spline, the only joint.
TEST(G3, EndSlopesMatchTheExactReference) {
  ASSERT_EQ(reference::g3_references().size(), 7u);
  for (const G3Reference& c : reference::g3_references()) {
    SCOPED_TRACE(c.name);
    if (c.dim == 2) {
      const BSpline s = planar(c);
      ASSERT_EQ(s.segment_count(), 2);
      expect_close(planar_end_kappa_slope(s, s.segments()[0], 1), c.slope_left, "dkappa/ds left");
      expect_close(planar_end_kappa_slope(s, s.segments()[1], 0), c.slope_right, "dkappa/ds right");
      const SplineReport r = judged_report(s, gates("g2-at-smooth-nodes"));
      ASSERT_EQ(r.joints.size(), 1u);
      expect_close(r.joints[0].joint.kappa_left, c.kappa_left, "kappa left");
      expect_close(r.joints[0].joint.kappa_right, c.kappa_right, "kappa right");
    } else {
      const SpaceSpline s = space(c);
      ASSERT_EQ(s.segment_count(), 2);
      expect_close(space_end_kappa_slope(s, s.segments()[0], 1), c.slope_left, "dkappa/ds left");
      expect_close(space_end_kappa_slope(s, s.segments()[1], 0), c.slope_right, "dkappa/ds right");
      const SpaceAnalysis a = analyze_space(s);
      ASSERT_EQ(a.joints.size(), 1u);
      expect_close(a.joints[0].kappa_left, c.kappa_left, "kappa left");
      expect_close(a.joints[0].tau_left, c.tau_left, "tau left");
      expect_close(a.joints[0].tau_right, c.tau_right, "tau right");
    }
  }
}

TEST(G3, VerdictsFollowTheReference) {
  int passing = 0, failing = 0;
  for (const G3Reference& c : reference::g3_references()) {
    SCOPED_TRACE(c.name);
    std::vector<GateViolation> v;
    if (c.dim == 2) {
      const SplineReport r = judged_report(planar(c), gates("g3-at-smooth-nodes"));
      ASSERT_EQ(r.gates.size(), 1u);
      EXPECT_EQ(r.gates[0].gate.kind, Gate::Kind::g3_at_smooth_nodes);
      v = r.gates[0].violations;
    } else {
      const SpaceSpline s = space(c);
      v = space_g3_violations(s, analyze_space(s), kDefaultG2Tolerance);
    }
    EXPECT_EQ(v.empty(), c.g3);
    ++(c.g3 ? passing : failing);
    for (const GateViolation& x : v) {
      EXPECT_EQ(x.joint, 1);
      EXPECT_NE(x.message.find("at smooth joint 1"), std::string::npos) << x.message;
    }
  }
  EXPECT_EQ(passing, 3);  // the three splits
  EXPECT_EQ(failing, 4);  // the uniform spline and the three moved ones
}

const G3Reference& ref(const std::string& name) {
  for (const G3Reference& c : reference::g3_references())
    if (name == c.name) return c;
  throw std::logic_error(name);
}

// The uniform cubic is C2 (G2 holds exactly) and not G3: the slopes differ in sign.
TEST(G3, UniformCubicIsG2ButNotG3) {
  const BSpline s = planar(ref("uniform_cubic"));
  const SplineReport r = judged_report(s, gates("g2-at-smooth-nodes:0,g3-at-smooth-nodes"));
  ASSERT_EQ(r.gates.size(), 2u);
  EXPECT_TRUE(r.gates[0].pass());
  ASSERT_EQ(r.gates[1].violations.size(), 1u);
  const std::string& m = r.gates[1].violations[0].message;
  EXPECT_NE(m.find("dkappa/ds"), std::string::npos) << m;
  EXPECT_EQ(m.find("curvature "), std::string::npos) << m;  // the curvature agrees
  EXPECT_FALSE(r.pass);
  // The tolerance is relative to the larger slope: 0.57 / 0.55 needs tol > 1.04.
  EXPECT_FALSE(judged_report(s, gates("g3-at-smooth-nodes:1")).pass);
  EXPECT_TRUE(judged_report(s, gates("g3-at-smooth-nodes:1.1")).pass);
}

// Moving the third point from the joint keeps kappa and the tangent: g2 passes, g3 not.
TEST(G3, MovedThirdPointKeepsG2) {
  for (const char* name : {"split_cubic_moved", "split_rational_moved"}) {
    SCOPED_TRACE(name);
    const SplineReport r = judged_report(planar(ref(name)), gates("g2-at-smooth-nodes,g3-at-smooth-nodes"));
    EXPECT_EQ(r.gates[0].pass(), std::string(name) == "split_cubic_moved");
    EXPECT_FALSE(r.gates[1].pass());
  }
}

// 3D: moving P6 out of the plane changes torsion as well; a planar curve
// in 3D (tau = 0 on both sides up to rounding) agrees by the kappa floor.
TEST(G3, SpaceTorsionIsJudged) {
  const SpaceSpline moved = space(ref("split_space_moved"));
  const std::vector<GateViolation> v = space_g3_violations(moved, analyze_space(moved), 0.05);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_NE(v[0].message.find("torsion"), std::string::npos) << v[0].message;
  EXPECT_NE(v[0].message.find("dkappa/ds"), std::string::npos) << v[0].message;
  // The planar split cubic lifted into z = 0: tau = 0, G3.
  const G3Reference& flat = ref("split_cubic");
  const SpaceSpline lifted = space(flat);
  EXPECT_TRUE(space_g3_violations(lifted, analyze_space(lifted), 0.05).empty());
  expect_close(std::abs(space_end_kappa_slope(lifted, lifted.segments()[1], 0)), std::abs(flat.slope_right),
               "|dkappa/ds| lifted");
}

std::string space_json(const SpaceSpline& s) {
  std::string out = "{\"degree\": " + std::to_string(s.degree()) + ", \"knots\": [";
  for (std::size_t i = 0; i < s.knots().size(); ++i) out += (i ? ", " : "") + format_number(s.knots()[i], 17);
  out += "], \"points\": [";
  for (std::size_t i = 0; i < s.points().size(); ++i) {
    const Vec3& p = s.points()[i];
    out += std::string(i ? ", " : "") + "[" + format_number(p.x, 17) + ", " + format_number(p.y, 17) + ", " +
           format_number(p.z, 17) + "]";
  }
  return out + "]}";
}

TEST(G3, SpaceReportAndCommandLine) {
  const std::string pass = test::write("g3_split_space.json", space_json(space(ref("split_space"))));
  const std::string fail = test::write("g3_split_space_moved.json", space_json(space(ref("split_space_moved"))));
  SpaceReportOptions o;
  o.gates = {*parse_gate("g3-at-smooth-nodes")};
  o.fixes = false;
  o.regions = false;
  EXPECT_TRUE(space_report(pass, o).gates.at(0).pass());
  const SpaceReport bad = space_report(fail, o);
  EXPECT_FALSE(bad.gates.at(0).pass());
  EXPECT_FALSE(bad.pass);
  const std::string out = (test::scratch() / "g3_out").string();
  // Only gates asked for: the curve passes when they do, monotone or not (as a planar report).
  const test::Outcome ok = test::run("report " + pass + " --require g3-at-smooth-nodes --no-thumbnails --out " + out);
  EXPECT_EQ(ok.code, 0) << ok.out << ok.err;
  EXPECT_NE(ok.out.find(" 0 findings;"), std::string::npos) << ok.out << ok.err;
  const test::Outcome no = test::run("report " + fail + " --require g3-at-smooth-nodes:0.05 --no-thumbnails --out " + out);
  EXPECT_EQ(no.code, 1) << no.err;
  EXPECT_NE(no.out.find(" 1 finding;"), std::string::npos) << no.out << no.err;
  const std::string json = test::slurp(out + "/report.json");
  EXPECT_NE(json.find("\"gate\":\"g3-at-smooth-nodes:0.05\""), std::string::npos) << json;
  EXPECT_NE(json.find("at smooth joint 1 (t = 1): not G3 within 0.05"), std::string::npos) << json;
  const test::Outcome bad_tol = test::run("report " + pass + " --require g3-at-smooth-nodes:x --out " + out);
  EXPECT_EQ(bad_tol.code, 2);
  EXPECT_NE(bad_tol.err.find("g3-at-smooth-nodes:x' needs a relative tolerance >= 0 (g3-at-smooth-nodes:0.05)"),
            std::string::npos)
      << bad_tol.err;
}

// cmr fix has no search for G3: refused in one line, nothing written.
TEST(G3, FixRefusesTheGate) {
  const std::string out = (test::scratch() / "g3_fixed.ufo").string();
  const test::Outcome r = test::run(std::string("fix ") + CMR_SOURCE_DIR + "/examples/ufo/Sans.ufo --glyph O --require g3-at-smooth-nodes --out " + out);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "cmr: --require g3-at-smooth-nodes:0.05: cmr fix has no certified fix for G3 (it keeps g2 at most)\n");
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(G3, Parsing) {
  const std::optional<Gate> g = parse_gate("g3-at-smooth-nodes");
  ASSERT_TRUE(g);
  EXPECT_EQ(g->kind, Gate::Kind::g3_at_smooth_nodes);
  EXPECT_EQ(g->tolerance, kDefaultG2Tolerance);
  EXPECT_EQ(to_string(*parse_gate("g3-at-smooth-nodes:0.01")), "g3-at-smooth-nodes:0.01");
  for (const char* bad : {"g3-at-smooth-nodes:", "g3-at-smooth-nodes:-1", "g3-at-smooth-nodes:nan"})
    EXPECT_THROW(parse_gate(bad), InputError) << bad;
}

}  // namespace
}  // namespace cmr::report

namespace cmr::report {
namespace {

// A closed uniform cubic on a square's corners: by its symmetry each joint
// is a mirror point of kappa, so dkappa/ds on both sides differ in sign, at
// every joint, the seam (joint 4) included; the square's C2 keeps G2.
TEST(G3, TheSeamIsJudgedLikeEveryJoint) {
  const BSpline s = BSpline::make_closed(3, {0, 1, 2, 3, 4}, {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}}, "square");
  const SplineReport r = judged_report(s, gates("g2-at-smooth-nodes:0,g3-at-smooth-nodes"));
  EXPECT_TRUE(r.gates[0].pass());
  const std::vector<GateViolation>& v = r.gates[1].violations;
  ASSERT_EQ(v.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(v[static_cast<std::size_t>(k)].joint, k + 1);
    const int left = k, right = (k + 1) % 4;
    const double a = planar_end_kappa_slope(s, s.segments()[static_cast<std::size_t>(left)], 1);
    const double b = planar_end_kappa_slope(s, s.segments()[static_cast<std::size_t>(right)], 0);
    EXPECT_NE(a, 0);
    EXPECT_EQ(a, -b);
  }
}

}  // namespace
}  // namespace cmr::report
