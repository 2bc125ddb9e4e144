#pragma once
// Curvature (and torsion) monotonicity of space curves, certified (issue 25).
//
// Per segment (Bezier points B of the span, exact from the knots and the
// double control points):
//  * curvature: Algorithm 1 on the Bernstein coefficients of
//    lambda3 = (|c|^2)' g - 3 |c|^2 g' (c = P' x P'', g = |P'|^2;
//    bezierize/space_lambda.hpp), whose sign is that of d kappa / dt: kappa
//    is unsigned in space, so "increasing" means |kappa| grows. The rules,
//    the traversal and the fold are the plane's (decide.hpp); coefficients
//    with error bounds first, exact rationals where a sign is uncertain.
//    lambda3 == 0 (c == 0: a straight segment) is `constant`.
//  * zero curvature (the analogue of an inflection): kappa = 0 exactly where
//    c = 0, i.e. where |c|^2 = 0. |c|^2 >= 0 has non-negative values; every
//    Bernstein coefficient certainly > 0 proves no zero; otherwise its exact
//    roots in [0, 1] are isolated (roots.hpp) and each is a common root of
//    the three components of c. An interior one makes lambda3 change sign,
//    so the segment is not monotone (Algorithm 1 finds that by itself).
//  * cusp: P' = 0 somewhere in the closed span (|P'|^2 = 0, decided the same way).
//  * torsion (option): Algorithm 1 on T = N' |c|^2 - N (|c|^2)',
//    N = det(P', P'', P'''), whose sign is that of d tau / dt where c != 0;
//    N == 0 (a planar segment) is `constant` (tau == 0). The sign of N on the
//    segment (torsion_sign: +1, -1, 0 when it changes or is identically 0).
// Joints: continuity from the knots; kappa on both sides from the end legs a,
// b (kappa = (d-1)/d |a x b| / |a|^3, kappa^2 exact, then one square root);
// the exact sign of the jump kappa_R - kappa_L (of kappa_R^2 - kappa_L^2);
// G1 (tangent angle within tolerance), G2 (G1, equal kappa within tolerance,
// and, where kappa > 0, the osculating planes' normals within the angle);
// torsion on both sides tau = (d-2)/d det(a, b, c) / |a x b|^2 and the exact
// sign of its jump (0 where C^3 by the knots or where kappa = 0).
// Verdicts: part_verdict of the plane (analyze.hpp) in CMRWI mode on these
// classes and jumps, so the spline-level rules are the plane's (constant
// segments go with either direction; a jump at a joint must follow the
// direction; a closed spline's seam is judged like every other joint).
#include <optional>
#include <vector>

#include "bezierize/analyze.hpp"
#include "spline/space.hpp"

namespace cmr {

struct SpaceAnalyzeOptions {
  int max_depth = kDefaultDepth;  ///< D of Algorithm 1, 0..kMaxDepth
  bool torsion = false;           ///< also judge torsion monotonicity
  ContinuityTolerances continuity;
  /// With torsion: a segment whose |tau| is at most this at its ends and at
  /// kTorsionSamples points between them is planar (its torsion class
  /// `constant`, as for N == 0 exactly): a CAD curve lying in a plane up to
  /// the rounding of its data (tau ~ 1e-6) is not judged on that noise.
  /// 0 (the default): only N == 0 exactly is planar. >= 0, finite.
  double torsion_tolerance = 0;
};

/// How many points between a segment's ends torsion_tolerance looks at.
inline constexpr int kTorsionSamples = 32;

struct SpaceSegmentResult {
  MonotonicityResult curvature;  ///< Algorithm 1 on lambda3 (constant: straight)
  bool exact_used = false;       ///< the exact fallback ran (curvature or torsion)
  bool straight = false;         ///< c == 0: kappa == 0 on the whole segment
  bool cusp = false;             ///< P' = 0 somewhere in the closed span
  /// Parameters in the closed span where kappa = 0 (c = 0), ascending, each
  /// the double nearest to a point of its exact root's enclosure (exact at
  /// the ends); empty when straight.
  std::vector<double> zero_curvature;
  std::optional<MonotonicityResult> torsion;  ///< Algorithm 1 on T (with options.torsion)
  int torsion_sign = 0;                       ///< sign of N when certainly constant on the segment
  /// With options.torsion: parameters strictly inside where N = det(P', P'', P''')
  /// changes sign (tau changes sign there; exact root isolation, as zero_curvature).
  std::vector<double> torsion_sign_changes;
  /// With options.torsion: N == 0 exactly (the segment lies in a plane), or
  /// |tau| within options.torsion_tolerance (then torsion is `constant`).
  bool planar = false;
};

struct SpaceJoint {
  int index = 0;  ///< the joint starts segment index (N: a closed spline's seam)
  double knot = 0;
  int multiplicity = 0;
  int continuity = 0;
  double kappa_left = 0, kappa_right = 0;  ///< NaN at a zero tangent
  int jump = 0;                            ///< exact sign of kappa_right - kappa_left
  bool zero_tangent = false;
  double angle_deg = 0;           ///< between the end tangents (NaN at a zero tangent)
  double normal_angle_deg = 0;    ///< between the osculating planes' normals c (NaN where kappa = 0)
  bool g1 = false, g2 = false;
  double tau_left = 0, tau_right = 0;  ///< NaN where kappa = 0 (0 for degree 2)
  int torsion_jump = 0;                ///< exact sign of tau_right - tau_left (0 where C^3 or undefined)
};

struct SpaceAnalysis {
  std::vector<SpaceSegmentResult> segments;
  std::vector<SpaceJoint> joints;  ///< joints[i-1] starts segment i
  std::optional<SpaceJoint> seam;  ///< closed splines
  Direction curvature = Direction::undecided;  ///< the spline's |kappa| (part_verdict, CMRWI rules)
  std::optional<Direction> torsion;            ///< with options.torsion
  bool cusp = false;
  bool zero_curvature = false;  ///< kappa = 0 somewhere (not counting straight segments)
  /// With options.torsion: every segment is planar (tau = 0 on each, up to
  /// the tolerance): every segment's torsion is `constant`, the curve's
  /// verdict follows the planar rules (constant pieces go with either
  /// direction: `increasing`), and reports label it "zero (planar pieces)",
  /// as the planar report labels a curve of straights "straight". (Pieces in different planes meeting at a corner
  /// of the osculating plane are each planar too.)
  bool planar = false;
  std::vector<int> joint_conflicts;
  int exact_segments = 0;
};

/// InputError for a depth outside 0..kMaxDepth or bad tolerances.
SpaceAnalysis analyze_space(const SpaceSpline& spline, const SpaceAnalyzeOptions& options = {});

/// One segment's classes and facts (what analyze_space reports for it).
SpaceSegmentResult space_segment(const SpaceSpline& spline, const Segment& s, const SpaceAnalyzeOptions& options);
/// The joint between segments left and right (right = left + 1, or 0 for the seam).
SpaceJoint space_joint(const SpaceSpline& spline, int left, int right, const ContinuityTolerances& tolerances);
/// A curvature extremum inside a segment: a root of lambda3 where it changes
/// sign (exact root isolation, roots.hpp), at parameter t (the double nearest
/// to a point of an enclosure at most 1e-12 of the span wide, exact at
/// halving points).
struct SpaceExtremum {
  double t = 0;
  bool maximum = false;  ///< lambda3 goes + to -: |kappa| has a maximum
};
/// The curvature extrema strictly inside segment s (none for a straight one).
std::vector<SpaceExtremum> space_curvature_extrema(const SpaceSpline& spline, const Segment& s);

/// The spline verdict of given segment results and joints (the rules above):
/// curvature, or torsion when `torsion` is set.
Direction space_verdict(const SpaceSpline& spline, const std::vector<SpaceSegmentResult>& segments,
                        const std::vector<SpaceJoint>& joints, const std::optional<SpaceJoint>& seam, bool torsion,
                        std::vector<int>* conflicts = nullptr);

}  // namespace cmr
