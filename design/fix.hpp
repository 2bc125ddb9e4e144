#pragma once
// The nearest certified repair (`cmr fix`): move the fewest control points
// the least distance so that the curve meets a requirement, and prove it.
//
//   fix(spline, request) -> FixResult
//
// Every answer carries a certificate: the fixed spline re-judged by analyze()
// (the verdict code of `cmr analyze` and `cmr report`), so a "fixed" answer is
// never contradicted by exact arithmetic. The search itself only ever keeps
// positions that the certified classifiers accept (RegionProblem::classify,
// i.e. the label every region backend draws; or analyze on the moved spline).
//
// Units of motion. A control point moves freely (2 degrees of freedom) unless
// a tie holds it (FixRequest::keep):
//  * keep g1: at a joint that is G1 but not C1 by its knots (a Bezier node with
//    a corner-capable knot, e.g. a font's smooth on-curve point) the node moves
//    only as the paper's rigid group (node and both handles translated
//    together, RegionRequest::with), and each handle only slides along the
//    tangent line through the node (1 degree of freedom), so the handles stay
//    collinear with the node exactly as the tangent direction is unchanged.
//    A handle between two such nodes cannot move.
//  * keep g2: also, at a joint that is G2 but not C2 by its knots, the points
//    that determine either side's curvature there (the 2-jet, found by the
//    Bezier extraction's dependence) move only as one translation (which
//    keeps both curvatures), led by the joint's node; they are frozen when
//    the node may not move.
//  * joints that are C1 (C2) by their knots are G1 (G2) whatever moves.
//
// Search (design/fix.cpp; its parts in design/fix_search.cpp):
//  1. One unit, nearest: for a 2-D unit, certified labels on a square grid
//     centred on the point, its half-width doubling from 1/16 of the curve
//     size up to max_move until a passing position is found; a finer grid
//     over the disc of that distance; up to six passing cells within two cell
//     diagonals of the best become seeds, and from each a golden-section
//     search over the angle of a ray from the point, each ray's passing
//     distance found by bisection to the tolerance. A 1-D unit bisects
//     between its line's nearest passing cell and the cell before it. Where
//     the region is not thinner than one cell of the first grid that reaches
//     it, the answer is within `tolerance` of the nearest passing position
//     (tested against a dense brute-force label map,
//     tests/design/fix_test.cpp).
//     Below the first cell (2-D units; region requirements and
//     curvature-extrema-at-nodes, without a caller's judge): where the
//     region is thinner than a cell (a sliver along an edge, a wedge tip),
//     levels halving the cell classify the children of every passing cell
//     and its 8 neighbours, then flood the 5x5 neighbours of each new passing
//     child, pruned by the lower distance bound against the best distance D,
//     down to a cell of D/512 (budget: 16 first grids of calls); seeds come
//     from the finest level. The answer is the nearest candidate (seed
//     answers, seeds, first-grid cells) the requirement itself accepts (for
//     cmr the labels are Algorithm 2, the certificate exact inflections).
//     Tested: within 1% (+ tolerance) of a 384x384 brute-force map's nearest
//     passing pixel on 40 seeded cubic Beziers and 20 uniform cubic
//     B-splines under cmr (tests/design/fix_nearest_test.cpp).
//  2. Several units: when no single unit fixes the curve (or with
//     FixRequest::together), units are moved one after the other, each to the
//     nearest position that lowers the count of violations; when no single
//     unit lowers it (with G1 kept, a segment whose two handles must both
//     slide, or a node group that must move with a handle), two units at
//     once: every pair acting on a common failing check, its nearest
//     position in the pair's 2-4 coordinates (a grid and rays for two
//     slides, rays in 96 fixed directions otherwise), the cheapest pair
//     taken. A tied handle never reaches its node (the tangent would turn
//     round). Then a compass search over all moved degrees of freedom
//     lowers the total squared displacement, each trial projected radially
//     onto the passing side by bisection and kept only when the classifier
//     accepts it. A local minimum, not a global one.
//  The kinds no-inflection and g2 have no region problem: each position
//  re-judges the checks the move touches (eta's sign, error-bounded first
//  and exact where undecided; the joint curvatures), and the certificate is
//  analyze, as for every kind.
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bezierize/analyze.hpp"
#include "spline/bspline.hpp"
#include "spline/limits.hpp"

namespace cmr {

/// What the fixed curve must satisfy (the requirement of `cmr report
/// --require`, and the curvature-extrema-at-nodes gate).
struct FixRequirement {
  enum class Kind : std::uint8_t { cmrwi, cmr, split, each_piece, extrema_at_nodes, no_inflection, g2, each_run };
  /// Which extremum split:S asks for at joint S, read in |kappa| as the
  /// report's gates read it (bezierize/extremum_terms.hpp): sharpest (largest
  /// |kappa|) or flattest (smallest), whatever the direction of travel.
  enum class Extremum : std::uint8_t { any, sharpest, flattest };
  Kind kind = Kind::cmr;
  int split = 0;                      ///< joint S (Kind::split)
  Extremum extremum = Extremum::any;  ///< (Kind::split)
  /// Kind::g2: |kappa_l - kappa_r| <= g2_tolerance * max(|kappa_l|, |kappa_r|)
  /// at every smooth joint (the report's g2-at-smooth-nodes:tol).
  double g2_tolerance = 0.05;
  /// Kind::each_piece: the groups' cut joints (AnalyzeOptions::splits; empty:
  /// every joint, each segment its own piece). Set by resolve_requirement
  /// for each_run.
  std::vector<int> cuts;
  /// The judged segments (AnalyzeOptions::segments; all when empty): only
  /// they must meet the requirement, as `cmr analyze --segments` judges them.
  std::optional<SegmentRange> segments;
};

/// Kinds beyond the region requirements (docs/fix.md):
///  no_inflection: the curvature never changes sign (eta of one sign on every
///    judged segment, no inflection inside, the same sign on every segment
///    that is not straight, no cusp);
///  g2: every smooth joint (G1, finite curvatures) has curvatures within
///    g2_tolerance (the gate g2-at-smooth-nodes, judged on the certified joint
///    curvatures);
///  each_run: every run between two nodes (joints whose knot multiplicity is
///    at least the degree: a font's on-curve points) monotone on its own, in
///    either direction; resolve_requirement makes it each_piece with the
///    nodes as cuts (cmrwi when no joint inside the judged range is a node).
/// The text forms: "no-inflection", "g2-at-smooth-nodes[:tol]", "each-run".
FixRequirement resolve_requirement(const BSpline& spline, FixRequirement requirement);

/// Parses "cmrwi", "cmr", "split:S", "split:S:sharpest|flattest",
/// "each-piece", "curvature-extrema-at-nodes" (alias "extrema-at-nodes"), "no-inflection",
/// "g2-at-smooth-nodes[:tol]" and "each-run". "split:S:max|min" (signed curvature,
/// which flips with the direction of travel) is refused with a hint, as in
/// `cmr report`. InputError names the text otherwise.
FixRequirement parse_fix_requirement(const std::string& text);
/// The text parse_fix_requirement reads.
std::string to_string(const FixRequirement& requirement);

/// The analysis a requirement is judged on: depth, split joint (split mode
/// CMRWI, as `cmr report`).
AnalyzeOptions fix_analyze_options(const FixRequirement& requirement, int max_depth = kDefaultDepth);
/// Whether an analysis (made with fix_analyze_options) meets the requirement:
///  cmrwi / cmr: that verdict is increasing or decreasing (cmr with exact
///    inflections, SplineAnalysis::cmr, as report);
///  split:S: the split verdict is inc-dec or dec-inc; with :sharpest or
///    :flattest, the extremum at S has that |kappa| reading (split_extremum_kind);
///  each-piece: every piece monotone on its own, in either direction
///    (SplineAnalysis::each_piece is monotone);
///  curvature-extrema-at-nodes: every segment's curvature is certified monotone
///    (Algorithm 1: increasing, decreasing or constant), so no extremum lies
///    inside a segment. This is the gate's sufficient condition: a touching
///    zero of lambda that the gate would not count, or the depth limit, fails it.
///  no-inflection, g2: see FixRequirement; each-run as each-piece (the
///    analysis made with the resolved requirement's cuts).
bool requirement_holds(const SplineAnalysis& analysis, const FixRequirement& requirement);
/// requirement_holds(analyze(spline, fix_analyze_options(requirement, max_depth)), requirement).
bool requirement_holds(const BSpline& spline, const FixRequirement& requirement, int max_depth = kDefaultDepth);

/// How ties at joints are kept (see the header comment).
enum class Keep : std::uint8_t { none, g1, g2 };
/// "none", "g1", "g2".
const char* to_string(Keep keep);

/// What to fix and how. The CLI fills one; tests fill another.
struct FixRequest {
  FixRequirement requirement;  ///< default: cmr
  /// The points that may move (distinct indices 0..unique_point_count()-1).
  /// Empty: every point but an open spline's first and last. Each must act on
  /// a failing segment (InputError otherwise).
  std::vector<int> points;
  Keep keep = Keep::g1;  ///< ties kept at joints that have them
  /// Largest displacement of any one point; 0: the curve size (the diagonal
  /// of the control points' bounding box).
  double max_move = 0;
  /// Distance tolerance of the nearest position, relative to the curve size.
  double tolerance = 1e-6;
  int max_depth = kDefaultDepth;  ///< D of Algorithms 1 and 2
  int grid = 32;                  ///< cells per side of the search grids (8..512)
  /// Move the allowed points together to the least total squared
  /// displacement (a compass search from the best single fix) instead of
  /// reporting the best single-unit fix.
  bool together = false;
  int threads = 0;  ///< for the grids; 0: every core
  /// Wall-clock limit of the search in seconds (0: none); when it runs out,
  /// the best certified fix found so far is returned, or none.
  double max_seconds = 30;
  /// max_seconds counts the calling thread's CPU time (spline/cpu_clock.hpp),
  /// not the wall clock, so that a loaded machine ends the search at the
  /// same place: only with threads 1 (the search then runs on the calling
  /// thread; InputError otherwise).
  bool thread_cpu_clock = false;
  /// Limit of the search's evaluations (classifier or judge calls; 0:
  /// none), ended as by max_seconds. Unlike time, with one thread it ends
  /// the search at the same place on any machine and under any load.
  long max_evaluations = 0;
  /// The caller's cancel flag (may be null; the Python module's
  /// KeyboardInterrupt): once set, the search ends as when its time is up,
  /// and its result is to be dropped.
  const std::atomic<bool>* cancel = nullptr;
  /// A caller's own judge instead of the requirement (the report's gates):
  /// how many violations a spline has, 0 when it passes; called from the
  /// search's threads (must be thread-safe). The search then evaluates it on
  /// every moved spline (no region problem), a failing segment is any judged
  /// one, and certificate_holds is judge(fixed) == 0 (the certificate's
  /// analysis is still made with the requirement's options).
  std::function<int(const BSpline&)> judge;
};

/// One moved control point.
struct PointMove {
  int point = 0;
  Vec2 from{0.0}, to{0.0};
  double distance = 0;  ///< |to - from|
};

/// What one unit of motion alone reaches (the candidates of "each point in turn").
struct UnitFix {
  std::vector<int> points;  ///< the unit's points (leader first)
  bool slide = false;       ///< moves along a tangent line only
  bool found = false;
  Vec2 displacement{0.0};  ///< of the leader
  double distance = 0;     ///< |displacement|
};

struct FixResult {
  bool already = false;  ///< the input meets the requirement: nothing moved
  bool fixed = false;    ///< the certificate holds (requirement and ties)
  std::string reason;    ///< why not fixed (one line)
  /// Not fixed because no allowed point acting on a failing segment may move
  /// (each is fixed, or held by ties: a handle between two G1 nodes).
  bool nothing_moves = false;
  std::optional<BSpline> spline;  ///< the moved spline (the input when not fixed)
  std::vector<PointMove> moves;   ///< every point that moved
  double total_squared = 0;       ///< sum of squared displacements
  double max_distance = 0;        ///< largest displacement
  double size = 0;                ///< the curve size the tolerances scale with
  std::vector<int> failing_segments;  ///< of the input
  std::vector<int> tie_joints;        ///< joints whose G1 (G2) was kept
  std::vector<UnitFix> units;         ///< each unit's own nearest fix
  SplineAnalysis certificate;         ///< analyze(*spline, fix_analyze_options(...))
  bool certificate_holds = false;     ///< requirement_holds(certificate)
  bool ties_hold = false;             ///< every tie joint still G1 (G2) in the certificate
  long evaluations = 0;               ///< classifier calls
  double seconds = 0;
};

/// Diagonal of the control points' bounding box (1 when it is 0): the curve
/// size every tolerance and relative move of a fix scales with.
double curve_size(const BSpline& spline);

/// The exponent e by which fix() and space_fix() scale a curve of this size
/// (the diagonal of its control points' box) before their search: 0 within
/// 2^-128..2^128 (and for a size of 0 or not finite), else the exponent of
/// the size, so that the copy, times 2^-e (exact), has a size of 1..2. Their
/// searches square lengths in doubles, which overflow above about 2^511.
int fix_scale_exponent(double size);

/// Finds the fix. Throws InputError for a point out of range or repeated, a
/// point that acts on no failing segment, a requirement that does not fit
/// the spline (a split joint it lacks), a bad max_move, tolerance, grid or
/// depth. A search that finds nothing within max_move is not an error: the
/// result says fixed = false and why.
FixResult fix(const BSpline& spline, const FixRequest& request);

/// The points of segment s (unique indices): moving any of them changes it.
std::vector<int> segment_points(const BSpline& spline, const Segment& s);
/// The judged segments that fail the requirement on their own (not monotone,
/// undecided, or for cmr an exact inflection); when every one passes alone but
/// the curve fails (directions or jumps disagree), every judged segment.
std::vector<int> failing_segments(const BSpline& spline, const SplineAnalysis& analysis,
                                  const FixRequirement& requirement);

}  // namespace cmr
