#pragma once
// Internal to cmr::report: the grid descent's measures of how far a contour
// is from passing (report/glyph_fix.cpp, descent_of): Badness from the exact
// report, and QuickJudge's estimate of it in doubles.
#include <optional>
#include <vector>

#include "report/report.hpp"
#include "spline/bspline.hpp"
#include "spline/vec2.hpp"

namespace cmr::report::glyph_detail {

/// A curvature jump's distance from passing g2 at tolerance `tol`: its
/// relative size above tol; where one side is exactly straight (a line meets
/// a curve: the relative jump is 100 % until the curve's end curvature is
/// exactly 0), |kappa| size / (1 + |kappa| size) of the curved side, which
/// falls to 0 as that curvature does (`size`: the curve's, curve_size).
double g2_excess(double kl, double kr, double tol, double size);

/// How far a spline is from passing every check, continuously: each
/// violation adds one to `count` and its distance from passing to `excess`
/// (an extremum or inflection inside a segment: its local parameter's
/// distance to the nearer end, where it leaves the segment; a curvature jump
/// at a smooth joint: its relative size above the gate's tolerance; anything
/// else, and a failing requirement: 1).
struct Badness {
  int count = 0;
  double excess = 0;
  double score() const { return excess + 1e-3 * count; }
};

/// The Badness of a report `r` of the checks `o` (`size`: the curve's, as for g2_excess).
Badness badness_of(const SplineReport& r, const ReportOptions& o, double size);

/// The descent's quick estimate of Badness in doubles (the exact judge
/// decides in the end): each segment's signed curvature sampled at
/// kQuickSamples + 1 parameters, a sign change of its differences an
/// extremum inside (excess: its distance to the nearer end); at each joint
/// the source's exact report calls smooth, the end curvatures' relative
/// difference above 0.9 of the tolerance (a margin for the exact judge).
/// Used only where every check is one of curvature-extrema-at-nodes,
/// max-extrema-per-segment:0.. (as extrema) and g2-at-smooth-nodes.
struct QuickJudge {
  bool extrema = false;
  bool g2 = false;
  double tolerance = 0.05;
  std::vector<char> g2_joint;              ///< per segment: the joint that starts it is judged (smooth in the source)
  std::vector<char> line_start, line_end;  ///< per segment: straight in the source (a line: never moves)
  double size = 1;                         ///< curve_size of the source
};
inline constexpr int kQuickSamples = 48;

/// The quick judge of source `s` under `o`; nullopt where a check is not one of those above.
std::optional<QuickJudge> quick_judge_of(const BSpline& s, const ReportOptions& o);

/// Signed curvature of a polynomial Bezier segment at t (de Casteljau on
/// the first and second hodographs).
double bezier_kappa(const std::vector<Vec2>& b, double t);

/// QuickJudge's estimate of the Badness of `s` (the contour at some position).
Badness quick_badness(const BSpline& s, const QuickJudge& q);

}  // namespace cmr::report::glyph_detail
