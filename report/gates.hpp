#pragma once
/// Type-design gates (`cmr report --require`, comma separated, beside cmrwi,
/// cmr and split:S), judged on a spline's certified report (report.hpp: the
/// extrema and inflections come from the exact roots of lambda and eta,
/// numeric/roots.hpp, and the curvature jumps at joints; nothing is
/// sampled). A "node" is a joint (on a closed spline the seam too): the
/// on-curve points of a font contour.
///
///  * curvature-extrema-at-nodes (alias: extrema-at-nodes, its name before
///    issue 36, which designers read as fontbakery's x/y-extremes rule): every
///    curvature extremum lies on a node (the rule type designers use); one
///    inside a segment is a violation, located by segment and parameter
///    (spline t and the segment's local t in [0, 1]).
///  * max-extrema-per-segment:N: at most N extrema strictly inside any one
///    segment.
///    Both extremum gates skip segments of constant curvature up to
///    ReportOptions::constant_tolerance (SpanReport::near_constant: an
///    imported circle arc, rounded to doubles, is exactly an ellipse arc with
///    a stationary point mid-way, at 1e-16 relative).
///  * g2-at-smooth-nodes[:tol]: at every smooth node (C1 or better, or G1 by
///    exact tangents; corners are exempt) the curvature on both sides agrees
///    within tol relative to the larger: |kl - kr| <= tol * max(|kl|, |kr|).
///    Default tol kDefaultG2Tolerance.
///  * g3-at-smooth-nodes[:tol]: at the same smooth nodes, G2 within tol and
///    equal dkappa/ds on both sides (and, on a space curve, equal torsion)
///    within tol relative to the larger, with a floor of kappa^2 (kappa for
///    torsion); exact end derivatives of the Bezier pieces, rational or not.
///    Default tol kDefaultG2Tolerance. report/g3.hpp.
///  * no-inflection: the curvature never changes sign.
///  * each-piece: every judged segment (piece) is monotone on its own, in
///    either direction (docs/semantics.md, "Each piece on its own"); a piece
///    that is not, or is undecided at the depth limit, is a violation.
///  * curvature-extrema-at-nodes:runs (alias: extrema-at-nodes:runs): the reading for quadratic (TrueType) outlines,
///    where every quadratic piece has its own curvature peak by construction
///    (a parabola's curvature peaks once, at its vertex: what the format
///    forces). A *node* is a joint whose knot multiplicity is at least the
///    degree (the curve passes through a control point there: an on-curve
///    point; implied on-curve midpoints are simple knots and no nodes). A
///    *run* is the chain of pieces between two consecutive nodes (the whole
///    contour, cyclically, when it has none), split at inflections. What the
///    designer controls is the height of each piece's peak (the largest
///    |kappa| over the piece: certified curvatures at its ends and at its
///    stationary points): along a run the peaks must rise to one highest
///    and fall. A piece whose peak is lower than the nearest different peak
///    on both sides (peaks within kRunPeakTolerance are one plateau) is a
///    valley: a violation located at its peak, whose `handles` are that
///    piece's own off-curve points (what to move). A loop without nodes is
///    allowed one valley. Runs of one or two pieces always pass (a cubic
///    piece's interior wiggles are extrema-at-nodes' and
///    max-extrema-per-segment's to judge). report/runs.cpp.
///
///  * xy-extrema-at-nodes[:U]: a node at every horizontal and vertical
///    tangent (the type designer's "points at extrema" rule, which fontbakery
///    ran through FontForge's and MS Font Validator's checks): every x or y
///    extremum of the outline (x' or y' changing sign, certified by exact
///    root isolation) lies on a node; one strictly inside a segment, or on a
///    joint that is no node, is a violation located by segment, t and the
///    point, whose fix is a node added there (de Casteljau split; cmr does
///    not write it back). An extremum poking less than U (default
///    kDefaultXyExtremumTolerance, in the outline's units) past its nearer
///    neighbouring node or extremum is tolerated. report/xy_extrema.hpp.
///
///  * g1-between-masters: every node smooth at the masters stays G1 at
///    every location between them (a designspace or a variable font; exact:
///    report/interpolation.hpp). Its findings name the location in the
///    user's axis values. g1-between-masters:DEG: a node whose tangents
///    turn by at most DEG degrees at both masters turns by at most DEG at
///    every location between (for masters rounded to the grid, whose smooth
///    nodes are rarely exactly collinear).
///  * curvature-between-masters: every segment whose curvature is monotone
///    at both masters of a piece stays monotone at every location between
///    (bezierize/between.hpp's bivariate certificate in (t, s)); otherwise
///    the first failing location and the instance's extremum.
///  * extrema-between-masters: curvature-extrema-at-nodes at every location:
///    the same certificate on every segment without an interior extremum at
///    the masters, and a node that is a curvature extremum at both masters
///    must stay one (lambda's signs at the node for every s).
///
/// Fixes: the smallest certified fix of each failing gate that has a fix
/// requirement (curvature-extrema-at-nodes, each-piece), report/certified_fix.hpp.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "spline/bspline.hpp"

namespace cmr::report {

struct SplineReport;
struct ReportOptions;

/// curvature-extrema-at-nodes:runs: peaks within this relative difference are one
/// plateau (a font's integer grid moves a peak by about 1/size of the curve).
inline constexpr double kRunPeakTolerance = 0.01;
/// Default tolerance of xy-extrema-at-nodes, in the outline's units (font
/// units: one unit of the integer grid; report/xy_extrema.hpp).
inline constexpr double kDefaultXyExtremumTolerance = 1.0;
/// Default relative tolerance of g2-at-smooth-nodes.
inline constexpr double kDefaultG2Tolerance = 0.05;

struct Gate {
  enum class Kind { extrema_at_nodes, max_extrema_per_segment, g2_at_smooth_nodes, no_inflection, each_piece,
                    unimodal_runs, xy_extrema_at_nodes, g1_between_masters,
                    curvature_between_masters, extrema_between_masters, g3_at_smooth_nodes };
  Kind kind = Kind::extrema_at_nodes;
  int max_extrema = 1;                     ///< max-extrema-per-segment:N
  double tolerance = kDefaultG2Tolerance;  ///< g2-at-smooth-nodes:tol, g3-at-smooth-nodes:tol
  double overshoot = kDefaultXyExtremumTolerance;  ///< xy-extrema-at-nodes:U
  double turn_degrees = 0;  ///< g1-between-masters:DEG (0: exactly G1; report/interpolation.hpp)
};

/// A gate's name with the old alias replaced: "extrema-at-nodes" ->
/// "curvature-extrema-at-nodes", "extrema-at-nodes:runs" ->
/// "curvature-extrema-at-nodes:runs"; any other text as it is.
std::string canonical_gate_name(const std::string& text);
/// A gate's text (or its alias), or nothing when `text` names no gate
/// (InputError when it names one with a bad argument: "max-extrema-per-segment:x").
std::optional<Gate> parse_gate(const std::string& text);
/// "curvature-extrema-at-nodes", "max-extrema-per-segment:2", "g2-at-smooth-nodes:0.05", "no-inflection",
/// "each-piece", "xy-extrema-at-nodes" (":U" when U is not the default): always the current name, never the alias.
std::string to_string(const Gate& gate);

/// Parses --require: comma-separated items, at most one of cmrwi / cmr /
/// split:S (options.require) and any gates (options.gates). InputError names
/// the item that is neither.
void parse_require_list(const std::string& text, ReportOptions& options);

/// Where a gate fails.
/// How a violation's severity search ended (report/severity.hpp).
enum class SeverityOutcome : std::uint8_t {
  moved,            ///< a move removes it (GateViolation::severity is its size)
  no_allowed_move,  ///< none of its segments' points may move (a line's, or held by smooth nodes): +inf
  none_found,       ///< the search found no move within its limits: +inf
};
/// report.json's words: "no allowed move", "none found" ("" for moved).
const char* severity_note(SeverityOutcome outcome);

struct GateViolation {
  int segment = -1;      ///< inside this segment, or
  int joint = -1;        ///< at this joint (index i starts segment i mod N; N is a closed spline's seam)
  double t = 0;          ///< spline parameter
  double local_t = 0;    ///< within the segment, 0..1 (segment violations)
  std::string message;   ///< one line: "curvature maximum inside segment 3 at t = 0.42"
  std::vector<int> handles;  ///< curvature-extrema-at-nodes:runs: the control points (distinct indices) to move
  /// The smallest certified move (largest point displacement, the spline's
  /// units) that removes this violation (report/severity.hpp); -1: not
  /// computed; +inf: none (severity_outcome says why).
  double severity = -1;
  SeverityOutcome severity_outcome = SeverityOutcome::moved;
  bool info = false;  ///< severity below ReportOptions::min_severity: reported, but it does not fail the gate
  /// Interpolation gates: the instance the page draws (the worst or first
  /// failing location), SplineReport::motions[motion] at motion_s on its
  /// masters' line (0..1); -1: none.
  int motion = -1;
  double motion_s = -1;
};

struct GateResult {
  Gate gate;
  std::vector<GateViolation> violations;
  /// No violation fails (info ones do not).
  bool pass() const {
    for (const GateViolation& v : violations)
      if (!v.info) return false;
    return true;
  }
};

/// A gate judged between masters (report/interpolation.hpp): it needs a
/// designspace or a variable font, and has no point-moving fix yet.
inline bool is_interpolation_gate(const Gate& gate) {
  return gate.kind == Gate::Kind::g1_between_masters || gate.kind == Gate::Kind::curvature_between_masters ||
         gate.kind == Gate::Kind::extrema_between_masters;
}

/// curvature-extrema-at-nodes:runs on one report (see the header comment).
std::vector<GateViolation> unimodal_run_violations(const SplineReport& report);

/// Every gate on one report (its extrema, inflections and joints).
std::vector<GateResult> check_gates(const SplineReport& report, const std::vector<Gate>& gates);

}  // namespace cmr::report
