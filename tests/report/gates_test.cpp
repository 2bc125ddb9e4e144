// Type-design gates: exact cases from symmetry, the seam judged like every
// other joint (rotating a closed contour's start changes nothing), extrema
// against dense sampling on real glyphs,
// --require parsing, and the commands on imported files and fonts.
#include <sys/stat.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>

#include "region/region.hpp"
#include "region/region_setup.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "tests/cli_util.hpp"
#include "io/font.hpp"
#include "io/svg.hpp"
#include "report/batch.hpp"
#include "report/report.hpp"

namespace cmr::report {
namespace {

const char* kDejaVu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
const char* kNimbus = "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf";

ReportOptions gates(const std::string& require) {
  ReportOptions o;
  o.regions = false;
  parse_require_list(require, o);
  return o;
}

const GateResult& result(const SplineReport& r, Gate::Kind kind) {
  for (const GateResult& g : r.gates)
    if (g.gate.kind == kind) return g;
  throw std::logic_error("gate not run");
}

/// parse_require_list refuses `text` with an InputError whose message holds `says`.
void expect_refused_saying(const std::string& text, const std::string& says) {
  ReportOptions p;
  try {
    parse_require_list(text, p);
    ADD_FAILURE() << text << " was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
}

// The closed uniform quadratic on a square's corners: four parabola pieces,
// each symmetric about its middle, so each has its curvature maximum at
// local t = 1/2 exactly and the minima are at the nodes; by the square's
// symmetry the curvature agrees on both sides of every node (G2).
TEST(Gates, SquareQuadraticHasOneMaximumMidSegment) {
  const BSpline s = BSpline::make_closed(2, {0, 1, 2, 3, 4}, {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}}, "square");
  const SplineReport r =
      judged_report(s, gates("curvature-extrema-at-nodes,max-extrema-per-segment:1,g2-at-smooth-nodes,no-inflection"));
  ASSERT_EQ(r.joints.size(), 4u);  // three inside and the seam
  EXPECT_EQ(r.joints.back().joint.index, 4);
  const GateResult& at_nodes = result(r, Gate::Kind::extrema_at_nodes);
  ASSERT_EQ(at_nodes.violations.size(), 4u);
  for (const GateViolation& v : at_nodes.violations) {
    EXPECT_EQ(v.local_t, 0.5) << v.message;
    // Counter-clockwise (kappa > 0): the maximum of kappa is the sharpest point.
    EXPECT_NE(v.message.find("sharpest point inside segment"), std::string::npos) << v.message;
  }
  // The four minima are on the nodes, the seam's among them.
  int on_joints = 0;
  for (const CurveEvent& e : r.extrema) on_joints += e.joint >= 0 ? 1 : 0;
  EXPECT_EQ(on_joints, 4);
  EXPECT_TRUE(result(r, Gate::Kind::max_extrema_per_segment).pass());
  EXPECT_TRUE(result(r, Gate::Kind::g2_at_smooth_nodes).pass());
  EXPECT_TRUE(result(r, Gate::Kind::no_inflection).pass());
  EXPECT_FALSE(r.pass);
  const SplineReport r0 = judged_report(s, gates("max-extrema-per-segment:0"));
  EXPECT_EQ(r0.gates[0].violations.size(), 4u);
}

// The model knows no gates: report_spline leaves them to the batch step
// (report -> gates -> fixes), whose judge_gates fills them and folds them
// into pass. With gates alone the requirement is informational.
TEST(Gates, ReportModelLeavesGatesToTheBatchStep) {
  const BSpline s = BSpline::make_closed(2, {0, 1, 2, 3, 4}, {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}}, "square");
  const ReportOptions o = gates("curvature-extrema-at-nodes");
  SplineReport r = report_spline(s, o);
  EXPECT_TRUE(r.gates.empty());
  EXPECT_TRUE(r.pass);  // nothing judged yet
  judge_gates(r, o);
  ASSERT_EQ(r.gates.size(), 1u);
  EXPECT_EQ(r.gates[0].violations.size(), 4u);
  EXPECT_FALSE(r.pass);
  const SplineReport j = judged_report(s, o);
  EXPECT_EQ(j.gates.size(), 1u);
  EXPECT_EQ(j.pass, r.pass);
  std::vector<ReportInput> inputs(1);
  inputs[0].file = "square";
  inputs[0].spline = s;
  const std::vector<SplineReport> batch = report_batch(std::move(inputs), o);
  ASSERT_EQ(batch.size(), 1u);
  ASSERT_EQ(batch[0].gates.size(), 1u);
  EXPECT_EQ(batch[0].gates[0].violations.size(), 4u);
  EXPECT_FALSE(batch[0].pass);
}

// An SVG circle (two arcs) becomes rational quadratics whose weights and
// points are rounded doubles: exactly, each piece is an ellipse arc with a
// stationary curvature mid-way, so the verdicts are non-monotone (cmr stays
// exact). Its certified curvature spread is at the level of rounding, far
// below the constant tolerance, so the extremum gates read the pieces as
// arcs of constant curvature; with tolerance 0 they are flagged. The square
// quadratic's spread is checked against dense sampling of kappa and is far
// above the tolerance.
TEST(Gates, RoundedCircleArcsAreConstantWithinTheTolerance) {
  const auto paths = import::parse_path_data("M 90 50 A 40 40 0 0 1 10 50 A 40 40 0 0 1 90 50 Z", "circle");
  ASSERT_EQ(paths.size(), 1u);
  const BSpline circle = import::to_bspline(paths[0]);
  ASSERT_TRUE(circle.is_rational());
  const SplineReport r = judged_report(circle, gates("curvature-extrema-at-nodes,max-extrema-per-segment:0"));
  bool some_exact_extremum = false;
  for (const SpanReport& sp : r.spans) {
    EXPECT_TRUE(sp.near_constant) << "segment " << sp.segment.index;
    EXPECT_LT(sp.kappa_spread, 1e-12) << "segment " << sp.segment.index;
    EXPECT_GE(sp.kappa_spread, 0);
    some_exact_extremum = some_exact_extremum || !sp.extrema.empty();
  }
  EXPECT_TRUE(some_exact_extremum);  // the data is not exactly a circle: the gates have something to skip
  for (const GateResult& g : r.gates) EXPECT_TRUE(g.pass()) << to_string(g.gate);

  ReportOptions strict = gates("curvature-extrema-at-nodes");
  strict.constant_tolerance = 0;
  const SplineReport r0 = judged_report(circle, strict);
  EXPECT_FALSE(r0.gates[0].pass());
  for (const SpanReport& sp : r0.spans) EXPECT_EQ(sp.near_constant, sp.kappa_spread == 0);

  // A designed curvature change: the square quadratic's pieces, against
  // sampled curvature (the spread's extremes are at the ends and mid-way).
  const BSpline square = BSpline::make_closed(2, {0, 1, 2, 3, 4}, {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}}, "square");
  const SplineReport rs = judged_report(square, gates("curvature-extrema-at-nodes"));
  for (const SpanReport& sp : rs.spans) {
    double lo = segment_end_curvature(square, sp.segment, 0), hi = lo;
    auto consider = [&](double k) { lo = std::min(lo, k), hi = std::max(hi, k); };
    consider(segment_end_curvature(square, sp.segment, 1));
    for (int q = 1; q < 1000; ++q) consider(curvature(square, sp.segment.a + (sp.segment.b - sp.segment.a) * q / 1000.0));
    EXPECT_NEAR(sp.kappa_spread, (hi - lo) / std::max(std::abs(lo), std::abs(hi)), 1e-9);
    EXPECT_GT(sp.kappa_spread, 0.1);
    EXPECT_FALSE(sp.near_constant);
  }
  EXPECT_EQ(rs.gates[0].violations.size(), 4u);
}

// Every node of a closed contour is judged alike: starting the period at
// another node gives the same extrema, inflections and violations.
TEST(Gates, SeamIsJudgedLikeEveryJoint) {
  const auto opts = gates("curvature-extrema-at-nodes,g2-at-smooth-nodes,no-inflection");
  for (const char* path : {kDejaVu, kNimbus}) {
    const import::Font font = import::read_font(path, import::parse_glyph_spec("S,O,a,g,R"));
    for (const import::Glyph& g : font.glyphs)
      for (const import::Contour& c : g.contours) {
        const BSpline& s = c.spline;
        const int m = s.unique_point_count();
        const std::vector<double> u = s.period_knots();
        const double T = u[m] - u[0];
        const SplineReport base = judged_report(s, opts);
        for (int shift : {1, 2, m / 2}) {
          std::vector<Vec2> P;
          std::vector<double> v;
          for (int k = 0; k < m; ++k) P.push_back(s.points()[(k + shift) % m]);
          for (int k = 0; k <= m; ++k) v.push_back(k + shift <= m ? u[k + shift] : u[k + shift - m] + T);
          const SplineReport r = judged_report(BSpline::make_closed(s.degree(), v, P), opts);
          const std::string what = s.name() + " shifted by " + std::to_string(shift);
          EXPECT_EQ(r.extrema.size(), base.extrema.size()) << what;
          EXPECT_EQ(r.inflections.size(), base.inflections.size()) << what;
          for (std::size_t k = 0; k < base.gates.size(); ++k)
            EXPECT_EQ(r.gates[k].violations.size(), base.gates[k].violations.size())
                << what << " gate " << to_string(base.gates[k].gate);
        }
      }
  }
}

// Extrema inside segments against dense sampling of kappa: each certified
// one has a sign change of the sampled dkappa next to it, and each sampled
// sign change well inside a segment is a certified extremum there.
TEST(Gates, ExtremaInsideSegmentsMatchDenseSampling) {
  const auto opts = gates("curvature-extrema-at-nodes");
  for (const char* path : {kDejaVu, kNimbus}) {
    const import::Font font = import::read_font(path, import::parse_glyph_spec("B,O,S,e,s"));
    for (const import::Glyph& g : font.glyphs)
      for (const import::Contour& c : g.contours) {
        const SplineReport r = judged_report(c.spline, opts);
        for (const Segment& seg : c.spline.segments()) {
          if (r.spans[seg.index].lambda_zero) continue;  // straight: constant curvature
          constexpr int kSamples = 4000;
          std::vector<double> kappa;
          for (int q = 0; q <= kSamples; ++q) kappa.push_back(curvature(c.spline, seg.a + (seg.b - seg.a) * q / kSamples));
          // Local t of sampled sign changes of dkappa, away from the ends;
          // differences below rounding noise of kappa count as no sign.
          double kmax = 0;
          for (double k : kappa) kmax = std::max(kmax, std::abs(k));
          std::vector<double> sampled;
          int last = 0;
          for (int q = 1; q <= kSamples; ++q) {
            const double dk = kappa[q] - kappa[q - 1];
            const double noise = 1e-9 * kmax;
            const int sign = dk > noise ? 1 : dk < -noise ? -1 : 0;
            if (sign != 0 && last != 0 && sign != last && q > 20 && q < kSamples - 20) sampled.push_back(double(q) / kSamples);
            if (sign != 0) last = sign;
          }
          std::vector<double> certified;
          for (const GateViolation& v : r.gates[0].violations)
            if (v.segment == seg.index) certified.push_back(v.local_t);
          std::size_t near = 0;
          for (double t : sampled)
            for (double x : certified) near += std::abs(t - x) < 3.0 / kSamples ? 1 : 0;
          EXPECT_EQ(near, sampled.size()) << c.spline.name() << " segment " << seg.index;
          for (double x : certified) {
            if (x > 0.01 && x < 0.99) {
              EXPECT_TRUE(std::any_of(sampled.begin(), sampled.end(), [&](double t) { return std::abs(t - x) < 3.0 / kSamples; }))
                  << c.spline.name() << " segment " << seg.index << " local t " << x;
            }
          }
        }
      }
  }
}

// A region for a point of a closed spline that the unrolled form repeats
// moves both copies (the problem's rigid group holds the twin), and each
// position's label is the verdict of the spline with the point moved there
// (BSpline::with_point moves the twin). This closed curve is nowhere
// monotone over its period, so the labels alone would not tell; the group does.
TEST(Gates, RegionsOfClosedSplinesMoveTheRepeatedPoint) {
  const BSpline s = BSpline::make_closed(3, {0, 1, 2, 3, 4, 5, 6}, {{2, 0}, {1, 1.5}, {-1, 1.5}, {-2, 0}, {-1, -1.5}, {1, -1.6}});
  for (int k : {0, 2, 4}) {  // 0 and 2 have twins (6 and 8), 4 has none
    RegionRequest rq;
    rq.point = k;
    rq.width = rq.height = 8;
    rq.mode = Mode::cmrwi;
    const RegionProblem problem = RegionProblem::make(s, rq);
    std::vector<int> group = problem.setup().group;
    std::sort(group.begin(), group.end());
    const std::vector<int> want_group = k < 3 ? std::vector<int>{k, k + 6} : std::vector<int>{k};
    EXPECT_EQ(group, want_group) << "point " << k;
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) {
        const Vec2 p = pixel_center(problem.view(), 8, 8, i, j);
        const SplineAnalysis a = analyze(s.with_point(k, p), {});
        const Direction want = a.cmrwi == Direction::increasing   ? Direction::increasing
                                 : a.cmrwi == Direction::decreasing ? Direction::decreasing
                                 : a.cmrwi == Direction::none       ? Direction::none
                                                                    : Direction::undecided;
        EXPECT_EQ(problem.classify(p).label, want) << "point " << k << " pixel " << i << "," << j;
      }
  }
}

TEST(Gates, RequireListParsing) {
  ReportOptions o;
  parse_require_list("cmr,curvature-extrema-at-nodes,max-extrema-per-segment:2,g2-at-smooth-nodes:0.1,no-inflection", o);
  ASSERT_TRUE(o.require.has_value());
  EXPECT_EQ(to_string(*o.require), "cmr");
  ASSERT_EQ(o.gates.size(), 4u);
  EXPECT_EQ(o.gates[1].max_extrema, 2);
  EXPECT_EQ(o.gates[2].tolerance, 0.1);
  EXPECT_EQ(to_string(o.gates[3]), "no-inflection");
  EXPECT_EQ(to_string(*parse_gate("g2-at-smooth-nodes")), "g2-at-smooth-nodes:" + std::to_string(kDefaultG2Tolerance).substr(0, 4));
  for (const char* bad : {"cmr,cmrwi", "extrema", "max-extrema-per-segment", "max-extrema-per-segment:-1",
                          "g2-at-smooth-nodes:x", "no-inflection:2", ""}) {
    ReportOptions p;
    EXPECT_THROW(parse_require_list(bad, p), InputError) << bad;
  }
  // cmr fix's each-run (a spline file's requirement, listed in its --help)
  // is no gate: the error names the gate it serves.
  expect_refused_saying("each-run", "as a gate (fonts, reports) it is curvature-extrema-at-nodes:runs");
}

// Issue 36: designers read "extrema-at-nodes" as fontbakery's x/y-extremes
// rule, so the gate is curvature-extrema-at-nodes; the old name (and its
// :runs reading) is read as an alias and never written.
TEST(Gates, OldNameIsAnAliasAndNeverWritten) {
  ReportOptions o;
  parse_require_list("extrema-at-nodes,extrema-at-nodes:runs,curvature-extrema-at-nodes", o);
  ASSERT_EQ(o.gates.size(), 3u);
  EXPECT_EQ(o.gates[0].kind, Gate::Kind::extrema_at_nodes);
  EXPECT_EQ(o.gates[1].kind, Gate::Kind::unimodal_runs);
  EXPECT_EQ(o.gates[2].kind, Gate::Kind::extrema_at_nodes);
  EXPECT_EQ(to_string(o.gates[0]), "curvature-extrema-at-nodes");
  EXPECT_EQ(to_string(o.gates[1]), "curvature-extrema-at-nodes:runs");
  EXPECT_EQ(canonical_gate_name("extrema-at-nodes"), "curvature-extrema-at-nodes");
  EXPECT_EQ(canonical_gate_name("extrema-at-nodes:runs"), "curvature-extrema-at-nodes:runs");
  EXPECT_EQ(canonical_gate_name("curvature-extrema-at-nodes"), "curvature-extrema-at-nodes");
  EXPECT_EQ(canonical_gate_name("extrema-at-nodesX"), "extrema-at-nodesX");
  EXPECT_EQ(canonical_gate_name("g2-at-smooth-nodes:0.05"), "g2-at-smooth-nodes:0.05");
  for (const char* bad : {"extrema-at-nodes:2", "curvature-extrema-at-nodes:2", "curvature-extrema"}) {
    ReportOptions p;
    EXPECT_THROW(parse_require_list(bad, p), InputError) << bad;
  }
  // --help lists the alias, and the error names both.
  const auto help = test::run("report --help");
  EXPECT_NE(help.out.find("curvature-extrema-at-nodes (alias: extrema-at-nodes)"), std::string::npos) << help.out;
  const auto fix_help = test::run("fix --help");
  EXPECT_NE(fix_help.out.find("curvature-extrema-at-nodes (alias: extrema-at-nodes)"), std::string::npos)
      << fix_help.out;
  expect_refused_saying("extrema", "extrema-at-nodes is an alias of curvature-extrema-at-nodes");
}

TEST(Gates, CommandsTakeImportedFilesAndFonts) {
  const auto dir = test::scratch() / "gates";
  std::filesystem::remove_all(dir);
  auto imported = test::run("import " + std::string(kDejaVu) + " --glyphs O,S --out " + (dir / "o").string());
  ASSERT_EQ(imported.code, 0) << imported.err;
  EXPECT_NE(imported.out.find("2 glyphs, 3 contours (quadratic, 2048 units per em)"), std::string::npos) << imported.out;
  for (const char* cmd : {"analyze", "segments"}) {
    const auto r = test::run(std::string(cmd) + " " + (dir / "o" / "O_c0.json").string());
    EXPECT_EQ(r.code, 0) << cmd << ": " << r.err;
  }
  const auto region = test::run("region " + (dir / "o" / "S_c0.json").string() +
                                " --point 1 --size 16x16 --backend cpu --png " + (dir / "r.png").string());
  EXPECT_EQ(region.code, 0) << region.err;
  const auto report = test::run("report " + std::string(kNimbus) + " --glyphs O,S,o --require curvature-extrema-at-nodes --out " +
                                (dir / "rep").string() + " --backend cpu");
  EXPECT_EQ(report.code, 1) << report.err;  // Nimbus' O has curvature maxima between its nodes
  const std::string html = test::slurp(dir / "rep" / "font.html");
  EXPECT_NE(html.find("<table id=\"glyphs\">"), std::string::npos);
  EXPECT_NE(html.find("data-name=\"S\""), std::string::npos);
  EXPECT_NE(html.find("<svg"), std::string::npos);
  const auto no_font = test::run("import " + (dir / "o" / "O_c0.json").string());
  EXPECT_EQ(no_font.code, 2);
  EXPECT_NE(no_font.err.find("not a font"), std::string::npos) << no_font.err;
  const auto bad_gate = test::run("report " + std::string(kNimbus) + " --require extrema --out " + (dir / "x").string());
  EXPECT_EQ(bad_gate.code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "x" / "report.json"));
  {
    std::ofstream(dir / "p.svg") << "<svg><path d='M0 0 A2 2 0 0 1 4 0 Z'/><path d='M0 0 C1 1 2 1 3 0'/></svg>";
  }
  const auto svg = test::run("import " + (dir / "p.svg").string() + " --out " + (dir / "svg").string());
  ASSERT_EQ(svg.code, 0) << svg.err;
  EXPECT_NE(svg.out.find("2 subpaths (1 rational)"), std::string::npos) << svg.out;
  EXPECT_EQ(test::run("analyze " + (dir / "svg" / "p_1.json").string()).code, 0);
  std::filesystem::remove_all(dir);
}

// Fonts and SVG files are read as every input is: a FIFO with no writer
// gives nothing and is refused at once (exit 2, one line), never waited on.
TEST(Gates, FontAndSvgInputsThatAreNotRegularFilesAreRefusedAtOnce) {
  const auto dir = test::scratch() / "fifo";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (const char* name : {"f.ttf", "f.svg"}) {
    const auto fifo = dir / name;
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    for (const std::string& cmd : {"import " + fifo.string() + " --out " + (dir / "o").string(),
                                   "report " + fifo.string() + " --no-thumbnails --out " + (dir / "r").string()}) {
      const auto t0 = std::chrono::steady_clock::now();
      const auto r = test::run(cmd);
      // At once: 10 s is far above a Release build's start (a sanitizer build starts slower: 60 s).
      EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(test::kSanitizerBuild ? 60 : 10)) << cmd;
      EXPECT_EQ(r.code, 2) << cmd << ": " << r.err;
      EXPECT_NE(r.err.find("empty (nothing came through the FIFO)"), std::string::npos) << cmd << ": " << r.err;
    }
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "o"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cmr::report

namespace cmr::report {
namespace {

// each-piece (issue 20, item 3): every piece monotone on its own, either way.
TEST(Gates, EachPieceJudgesEveryPieceOnItsOwn) {
  // The square's four parabolas each have their maximum mid-way: none is monotone.
  const BSpline square = BSpline::make_closed(2, {0, 1, 2, 3, 4}, {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}}, "square");
  ReportOptions o;
  o.regions = false;
  parse_require_list("each-piece", o);
  ASSERT_EQ(o.gates.size(), 1u);
  EXPECT_EQ(to_string(o.gates[0]), "each-piece");
  const SplineReport r = judged_report(square, o);
  ASSERT_EQ(r.gates.size(), 1u);
  ASSERT_EQ(r.gates[0].violations.size(), 4u);
  EXPECT_EQ(r.gates[0].violations[2].message, "segment 2 is not monotone on its own");
  EXPECT_FALSE(r.pass);
  // The wave: increasing, increasing, decreasing, increasing: each piece
  // monotone, though the whole is not and no two neighbours need alternate.
  const BSpline wave = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7, 8},
                                     {{0.058, 0.128}, {1.274, 0.936}, {2.065, -0.298}, {3.236, -0.998},
                                      {3.765, 0.132}, {5.069, -0.719}, {6.078, 0.783}});
  const SplineReport w = judged_report(wave, o);
  ASSERT_EQ(w.gates.size(), 1u);
  EXPECT_TRUE(w.gates[0].pass());
  EXPECT_TRUE(w.pass);
  EXPECT_THROW(parse_require_list("each-piece:2", o), InputError);
}

}  // namespace
}  // namespace cmr::report
