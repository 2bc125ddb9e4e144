// Sharpest and flattest (issue 20, item 1): the |kappa| reading of every
// extremum, the type-design gates and the split:S:sharpest|flattest
// requirements give the same answers whichever way a curve runs (reversing
// the parameter), mirrored (x -> -x), and for a closed contour traversed
// either way (TrueType outer contours run clockwise, CFF ones
// counter-clockwise). Seeded random splines; every transform is exact in
// double (negation), so the certified answers must agree exactly.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <tuple>

#include "bezierize/extremum_terms.hpp"
#include "io/font.hpp"
#include "report/extremum.hpp"
#include "report/batch.hpp"
#include "report/report.hpp"
#include "tests/test_util.hpp"

namespace cmr::report {
namespace {

ReportOptions with(const std::string& require) {
  ReportOptions o;
  o.regions = false;
  parse_require_list(require, o);
  return o;
}

BSpline mirrored(const BSpline& s) {
  std::vector<Vec2> p;
  for (int i = 0; i < s.unique_point_count(); ++i) p.push_back({-s.points()[i].x, s.points()[i].y});
  if (s.closed()) return BSpline::make_closed(s.degree(), s.period_knots(), p);
  return BSpline::make(s.degree(), s.knots(), p);
}

struct Summary {
  std::map<std::string, int> kinds;     // extremum kinds by |kappa|
  std::vector<bool> gate_pass;          // per gate
  std::vector<std::size_t> violations;  // per gate
  bool operator==(const Summary&) const = default;
};

Summary summary(const SplineReport& r) {
  Summary s;
  for (const CurveEvent& e : r.extrema) ++s.kinds[to_string(event_kind(r, e))];
  for (const GateResult& g : r.gates) {
    s.gate_pass.push_back(g.pass());
    s.violations.push_back(g.violations.size());
  }
  return s;
}

std::string text(const Summary& s) {
  std::string t;
  for (const auto& [k, n] : s.kinds) t += k + " " + std::to_string(n) + ", ";
  for (std::size_t i = 0; i < s.gate_pass.size(); ++i)
    t += std::string(s.gate_pass[i] ? "pass" : "fail") + "(" + std::to_string(s.violations[i]) + ") ";
  return t;
}

const char* kGates = "curvature-extrema-at-nodes,max-extrema-per-segment:1,no-inflection";

TEST(Orientation, ExtremumKindReadsAbsoluteCurvature) {
  // kappa > 0: the signed maximum is the sharpest point; kappa < 0 the flattest.
  EXPECT_EQ(extremum_kind(1, 1, 1), ExtremumKind::sharpest);
  EXPECT_EQ(extremum_kind(-1, 1, 1), ExtremumKind::flattest);
  EXPECT_EQ(extremum_kind(1, -1, -1), ExtremumKind::flattest);
  EXPECT_EQ(extremum_kind(-1, -1, -1), ExtremumKind::sharpest);
  // Across an inflection at a joint (opposite signs, or zero on one side).
  EXPECT_EQ(extremum_kind(1, -1, 1), ExtremumKind::inflection);
  EXPECT_EQ(extremum_kind(-1, 0, 1), ExtremumKind::inflection);
  // kappa touching 0 without changing sign: |kappa| has its minimum 0 there.
  EXPECT_EQ(extremum_kind(1, 0, 0), ExtremumKind::flattest);
  Joint j;
  j.kappa_left = -0.054;
  j.kappa_right = -0.06;
  EXPECT_EQ(split_extremum_kind(Split::inc_dec, j), ExtremumKind::flattest);  // #20: fig9b split 2
  EXPECT_EQ(split_extremum_kind(Split::dec_inc, j), ExtremumKind::sharpest);
  EXPECT_FALSE(split_extremum_kind(Split::inc_inc, j).has_value());
}

TEST(Orientation, ReversingMirroringAndContourDirectionGiveTheSameAnswers) {
  std::mt19937_64 rng(2020);
  std::uniform_real_distribution<double> step(0.5, 1.5);
  int extrema = 0, sharpest = 0, flattest = 0, split_passes_seen = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const bool closed = trial % 3 == 2;
    const int d = 2 + trial % 2, m = 6 + trial % 3;
    std::vector<double> knots{0};
    const int count = closed ? m + 1 : m + d - 1;
    while (static_cast<int>(knots.size()) < count) knots.push_back(knots.back() + step(rng));
    std::vector<Vec2> pts = test::random_points(rng, m, 1.0);
    if (closed)  // a star-shaped loop: points at increasing angles, radius noise
      for (int i = 0; i < m; ++i) {
        const double a = 6.283185307179586 * i / m, r = 1 + 0.4 * pts[i].x;
        pts[i] = {r * std::cos(a), r * std::sin(a)};
      }
    const BSpline s = closed ? BSpline::make_closed(d, knots, pts) : BSpline::make(d, knots, pts);
    const std::vector<std::pair<const char*, BSpline>> variants = {
        {"reversed", s.reversed()}, {"mirrored", mirrored(s)}, {"mirrored and reversed", mirrored(s).reversed()}};
    const SplineReport base = judged_report(s, with(kGates));
    const Summary want = summary(base);
    extrema += static_cast<int>(base.extrema.size());
    sharpest += want.kinds.count("sharpest") ? want.kinds.at("sharpest") : 0;
    flattest += want.kinds.count("flattest") ? want.kinds.at("flattest") : 0;
    for (const auto& [name, v] : variants) {
      const Summary got = summary(judged_report(v, with(kGates)));
      EXPECT_EQ(got, want) << "trial " << trial << " " << name << (closed ? " (closed)" : "") << ": " << text(got)
                           << " vs " << text(want);
    }
    if (closed) continue;
    // split:S:sharpest|flattest at joint S is the requirement at the mirrored
    // curve's joint S and the reversed curve's joint N-S.
    const int N = s.segment_count();
    for (int S = 1; S < N; ++S)
      for (const char* kind : {"sharpest", "flattest"}) {
        const auto passes = [&](const BSpline& c, int joint) {
          return judged_report(c, with("split:" + std::to_string(joint) + ":" + kind)).pass;
        };
        const bool p = passes(s, S);
        split_passes_seen += p;
        EXPECT_EQ(passes(s.reversed(), N - S), p) << "trial " << trial << " split " << S << " " << kind << " reversed";
        EXPECT_EQ(passes(mirrored(s), S), p) << "trial " << trial << " split " << S << " " << kind << " mirrored";
      }
  }
  // The family exercises both kinds (random splits seldom pass: see below).
  EXPECT_GT(extrema, 20);
  EXPECT_GT(sharpest, 5);
  EXPECT_GT(flattest, 5);
  (void)split_passes_seen;
}

// examples/wave.json: decreasing on segment 2, increasing on 3, kappa < 0 at
// joint 3: a signed minimum there, the sharpest point; and a signed maximum
// at joint 2 where kappa > 0, sharpest too. Reversed (segments 3-i, joint
// 4-S) and mirrored, the same requirements pass and fail.
TEST(Orientation, WaveSplitsReadTheSameWhicheverWayItRuns) {
  const BSpline wave = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7, 8},
                                     {{0.058, 0.128}, {1.274, 0.936}, {2.065, -0.298}, {3.236, -0.998},
                                      {3.765, 0.132}, {5.069, -0.719}, {6.078, 0.783}});
  const auto passes = [](const BSpline& c, int joint, int first, const char* kind) {
    ReportOptions o = with("split:" + std::to_string(joint) + ":" + kind);
    o.segments = SegmentRange{first, first + 1};
    return judged_report(c, o).pass;
  };
  for (const auto& [S, first, sharpest] : {std::tuple{3, 2, true}, std::tuple{2, 1, true}})
    for (const char* kind : {"sharpest", "flattest"}) {
      const bool want = (std::string(kind) == "sharpest") == sharpest;
      EXPECT_EQ(passes(wave, S, first, kind), want) << S << " " << kind;
      EXPECT_EQ(passes(wave.reversed(), 4 - S, 2 - first, kind), want) << S << " " << kind << " reversed";
      EXPECT_EQ(passes(mirrored(wave), S, first, kind), want) << S << " " << kind << " mirrored";
    }
}

// Real outlines: glyph contours of a TrueType font (quadratic; outer contours
// clockwise) and of a CFF font (cubic; outer contours counter-clockwise),
// each also mirrored, reversed (the other format's orientation) and both:
// the |kappa| kinds of the extrema and the type-design gates agree exactly.
TEST(Orientation, GlyphContoursReadTheSameMirroredAndReversed) {
  const std::vector<std::pair<std::string, bool>> fonts = {
      {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", false},                   // fonts-dejavu-core
      {"/usr/share/texmf/fonts/opentype/public/tex-gyre/texgyreheros-regular.otf", true}};  // fonts-texgyre
  int contours = 0;
  for (const auto& [path, cubic] : fonts) {
    const import::Font font = import::read_font(path, import::parse_glyph_spec("O,a,g,S,e,3"));
    ASSERT_EQ(font.cubic, cubic) << path;
    ASSERT_EQ(font.glyphs.size(), 6u) << path;
    for (const import::Glyph& g : font.glyphs)
      for (const import::Contour& c : g.contours) {
        const BSpline& s = c.spline;
        ASSERT_TRUE(s.closed());
        const Summary want = summary(judged_report(s, with(kGates)));
        ++contours;
        const std::vector<std::pair<const char*, BSpline>> variants = {
            {"reversed", s.reversed()}, {"mirrored", mirrored(s)}, {"mirrored and reversed", mirrored(s).reversed()}};
        for (const auto& [name, v] : variants) {
          const Summary got = summary(judged_report(v, with(kGates)));
          EXPECT_EQ(got, want) << path << " " << g.name << " contour " << c.index << " " << name << ": " << text(got)
                               << " vs " << text(want);
        }
      }
  }
  EXPECT_GE(contours, 16);
}

}  // namespace
}  // namespace cmr::report
