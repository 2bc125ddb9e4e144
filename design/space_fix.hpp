#pragma once
// The nearest certified repair of a space curve (`cmr fix` on a file with
// [x, y, z] points, issue 25; docs/fix.md, "Space curves"): move one control
// point the least distance, within a plane through it, so that |kappa| is
// monotone over the whole spline, and prove it.
//
//   space_fix(spline, request) -> SpaceFixResult
//
// Each candidate point K moves in the plane through K spanned by the request's
// directions (SpaceFixRequest::plane_text: xy, yz, zx or nine numbers whose
// U, V are used, the origin being K), or by default in K's default plane of
// `cmr region` (default_space_plane: the directions to its neighbours). The
// plane's directions are made orthonormal (Gram-Schmidt in doubles), so plane
// coordinates (a, b) are distances. The search is the plane's one-unit search
// of design/fix.hpp on the certified labels of SpaceRegionProblem::classify
// (the label `cmr region` draws for a space curve): a 32 x 32 grid centred on
// K, its half-width doubling from 1/16 of the curve size up to max_move until
// a position passes; a finer grid over the disc of that distance; up to six
// passing cells within two cell diagonals of the best become seeds, and from
// each a golden-section search over the angle of a ray from K, each ray's
// first passing distance found by scanning and bisection to the tolerance.
// Candidates are tried one at a time and the nearest fix is kept (several
// points moving together are not searched for space curves). Keep g1: the
// node of a joint that is G1 but not C1 by its knots does not move, and each
// of its handles only slides along the line through the node (1-D: a scan of
// 2048 samples each way, never reaching the node, then bisection), so the
// tangent direction is kept; a handle of two such joints does not move.
//
// Certificate: the moved point is rounded to doubles, the moved spline is
// judged by analyze_space (the verdict code of `cmr analyze` and `cmr report`
// for space curves), and a fix is reported only when that analysis meets the
// requirement (and the ties: with keep g1 / g2, every joint that is not C1 /
// C2 by its knots and was G1 / G2 stays so). Where rounding the point to
// doubles lands just outside the region, the point is pushed further along its
// ray (at most 12 doublings of the tolerance) until the certificate holds.
#include <optional>
#include <string>
#include <vector>

#include "design/fix.hpp"
#include "region/space_region.hpp"

namespace cmr {

struct SpaceFixRequest {
  /// false: |kappa| monotone over the whole spline (cmrwi, the space gate of
  /// `cmr report`); true (`--require cmr`): also no point of zero curvature
  /// and no cusp (kappa = 0 is space's analogue of an inflection).
  bool no_zero_curvature = false;
  /// Candidate points, each tried alone; every one must act on a failing
  /// segment or a joint in conflict. Empty: every such point but an open
  /// spline's two end points.
  std::vector<int> points;
  /// Points that must not move, whatever else holds (a STEP chain's edge
  /// keeps the points that carry its ends' jets: import::fix_step_chain).
  /// Left out of the default candidates; naming one in `points` is an
  /// InputError.
  std::vector<int> held;
  /// The plane's directions ("xy", "yz", "zx" or nine numbers, as `cmr region
  /// --plane`; the origin is each moved point itself). Empty: each point's
  /// default plane.
  std::string plane_text;
  Keep keep = Keep::g1;
  double max_move = 0;      ///< 0: the curve size
  double tolerance = 1e-6;  ///< relative to the curve size
  int max_depth = kDefaultDepth;
  double time_limit = 30;  ///< seconds for the whole search
};

struct SpacePointMove {
  int point = 0;
  Vec3 from{0.0}, to{0.0};
  double distance = 0;  ///< |to - from|
  SpacePlane plane;     ///< through `from`, orthonormal directions
};

/// Each candidate's own nearest fix (or why none).
struct SpaceUnitFix {
  int point = 0;
  bool found = false;
  double distance = 0;
  Vec3 displacement{0.0};
  std::optional<SpacePlane> plane;  ///< empty when the point has no plane (reason says why)
  std::string reason;               ///< when not found
};

struct SpaceFixResult {
  bool already = false;  ///< the input meets the requirement: nothing moves
  bool fixed = false;    ///< a certified fix was found (or already)
  std::vector<SpacePointMove> moves;  ///< one move, or none
  std::optional<SpaceSpline> spline;  ///< the fixed spline (the input when already)
  SpaceAnalysis certificate;          ///< analyze_space(*spline)
  bool certificate_holds = false;
  bool ties_hold = false;
  double size = 0;  ///< diagonal of the control points' bounding box
  double max_distance = 0, total_squared = 0;
  std::vector<int> failing_segments;  ///< of the input: not certified monotone
  std::vector<int> joint_conflicts;   ///< of the input
  std::vector<int> tie_joints;        ///< joints whose G1 (G2) is kept
  std::vector<SpaceUnitFix> units;
  std::string reason;  ///< one line, when not fixed
  long evaluations = 0;
  double seconds = 0;
};

/// InputError for bad options (depth, negative max_move or tolerance, a point
/// out of range or not acting on a failing segment, a bad --plane).
SpaceFixResult space_fix(const SpaceSpline& spline, const SpaceFixRequest& request);

/// Whether an analysis meets the requirement (|kappa| monotone; with
/// no_zero_curvature also no zero curvature and no cusp).
bool space_fix_passes(const SpaceAnalysis& analysis, bool no_zero_curvature);

/// The spline with unique point k (and its twin on a closed spline) at q.
SpaceSpline with_point_moved(const SpaceSpline& spline, int k, const Vec3& q);

}  // namespace cmr
