#pragma once
// Spline-level verdicts over all segments (CAD&A 2024 §4.2).
//
//  * CMRWI: every segment monotone in one common direction (constant, i.e.
//    straight, segments go with either); at a joint where the spline is not
//    C^2 (knot multiplicity >= d-1, so curvature may jump) the jump must go the
//    same way. If every segment is constant the verdict follows Algorithm 1's
//    rule order (condition (1) first): increasing.
//  * CMR: CMRWI and no inflection. Two readings are kept (README, "Semantics"):
//    - SplineAnalysis::cmr, what analyze and report state: no *exact*
//      inflection. An inflection is a sign change of the curvature: of eta
//      strictly inside a segment (certified root isolation), or across a
//      joint or a run of straight segments (kappa = 0 there). A zero of eta
//      at a segment's end (a curve leaving a straight with zero curvature)
//      or a touching zero is not one.
//    - SplineAnalysis::cmr_algorithm2, the paper's Algorithm 2 as stated
//      (nu_0 nu_last <= 0 -> inflection, depth limit -> undecided): what the
//      region engine draws for --mode cmr (region/region.hpp, the shader).
//      It is stricter: a pass under Algorithm 2 is a pass under the exact
//      reading, never the reverse.
//  * Straight segments (lambda == 0, equivalently eta == 0 for a polynomial
//    piece) have constant curvature 0: class `constant`, no inflection, and
//    they go with either direction (non-strict monotonicity). The paper's
//    rule that conditions (1) and (2) holding together mean "not monotone" is
//    not used: it would reject every curve that leaves a straight. A spline
//    of straight segments only is reported `increasing` (Algorithm 1 checks
//    condition (1) first).
//  * Split at joint s (1 <= s <= N-1): segments 0..s-1 against s..N-1, each
//    part judged as above (in CMRWI or CMR mode); the jump at joint s itself is
//    free. inc-dec puts a curvature maximum at the joint, dec-inc a minimum.
// Verdicts: a part that is not monotone makes "none"; otherwise one that is
// undecided (depth limit) makes "undecided".
//  * Segment control (bezierize/segments.hpp): with options.segments only
//    those segments are classified and judged (the verdicts above, the split
//    and the joint conflicts are of that range); with options.splits the
//    range's groups between the joints get the alternation verdict.
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bezierize/classify.hpp"
#include "bezierize/segments.hpp"
#include "spline/bspline.hpp"

namespace cmr {

/// The verdicts of a spline (or a part of it): Direction for monotonicity,
/// Split for a split at a joint. They are also the labels of region pixels
/// (region.hpp): numbered so that code() is the label byte, 0 = fails.
enum class Direction : std::uint8_t { none = 0, increasing = 1, decreasing = 2, undecided = 3 };
/// inc_dec: signed curvature increases up to the joint and decreases after it.
enum class Split : std::uint8_t { none = 0, inc_inc = 1, inc_dec = 2, dec_inc = 3, dec_dec = 4, undecided = 5 };
enum class Mode : std::uint8_t { cmrwi, cmr };

const char* to_string(Direction d);
const char* to_string(Split s);

/// Certified relative error of every curvature value cmr reports (joint
/// kappa_left/right, the report's kappa): the sign is exact, the value is
/// within this factor of the exact curvature of the double input data.
inline constexpr double kKappaRelError = 1e-11;

/// Exact facts about one segment's geometry, beside Algorithms 1 and 2.
/// Decided with error-bounded arithmetic where that is certain, else with
/// exact rationals from the spline's double data.
struct SegmentShape {
  /// W = 0 somewhere in the closed span (rational splines; bspline.hpp): the
  /// curve passes through infinity. Decided exactly (segment_poles); then
  /// inflection is forced to present, the other fields are left default, and
  /// the segment's classes are forced to pole_class() (analyze).
  bool pole = false;
  std::vector<double> poles;  ///< the distinct parameters where W = 0 (segment_poles)
  bool straight = false;  ///< eta == 0: a straight segment (lambda == 0 too), curvature 0 where defined
  bool cusp = false;      ///< P'(t) = 0 for some t in the closed span: curvature unbounded or undefined there
  Inflection inflection = Inflection::none;  ///< present: eta changes sign at some t strictly inside (exact)
  bool kappa_zero_start = false, kappa_zero_end = false;  ///< zero curvature at that end: eta = 0, P' != 0 (not straight)
  /// Sign of the curvature just inside the start (the sign throughout when no
  /// inflection); 0 if straight. Of eta, or for a rational span of W D (kappa
  /// = W^3 D / |h|^3; W has one sign on a span without a pole). Algorithm 2's
  /// InflectionResult::kappa_sign is that of D alone (what the region engine
  /// and the shader compare): on a judged range without a pole W has one
  /// sign (it is continuous), so comparisons between segments agree.
  int kappa_sign = 0;
};
/// "pole", "cusp", "straight" or "regular" (in that order of precedence).
const char* shape_class(const SegmentShape& s);
/// "none", "start", "end" or "both": where eta is zero at the segment's ends.
const char* kappa_zero_at(const SegmentShape& s);

SegmentShape segment_shape(const BSpline& spline, const Segment& s);

/// Where the homogeneous weight W (bspline.hpp) vanishes on the closed span
/// [s.a, s.b] of a rational spline: empty when W has no root there (always
/// for a polynomial spline). Exact: W's Bernstein coefficients on the span
/// (the weights of segment_homogeneous_points) are first tested with error
/// bounds, then as exact rationals: all > 0 or all < 0 means no root;
/// otherwise isolate_roots (roots.hpp: exact halving with Descartes' rule,
/// square-free split for touching roots) decides, and each distinct root is
/// returned as the double nearest to a point of its enclosure (at most
/// 1e-12 of the span's length wide; a root at a knot or at a halving point is
/// exact). W == 0 on the whole span gives {s.a, s.b}.
std::vector<double> segment_poles(const BSpline& spline, const Segment& s);
/// Some segment of the spline has a pole (segment_poles is not empty).
bool has_pole(const BSpline& spline);

/// The sign of W at the start of segment s, exact (1 for a polynomial
/// spline): W's sign on the whole segment when it has no pole. The curvature
/// is W^3 D / |h|^3, so its sign is weight_sign * sign(D).
int weight_sign(const BSpline& spline, const Segment& s);

/// The classes of a straight polynomial segment (eta == 0 and lambda == 0):
/// what classify_segment returns for it (constant and, by Algorithm 2's
/// eta_0 eta_n <= 0, an inflection, both at depth 0; the exact path used).
SegmentClass straight_class();

/// The classes of a segment with a pole: non-monotone and an inflection, at
/// depth 0 (a curve through infinity has no monotone curvature).
SegmentClass pole_class();

/// Tolerances of the geometric continuity tests at joints.
struct ContinuityTolerances {
  double angle_deg = 1e-3;      ///< G1: the end tangents' directions differ by at most this angle (degrees)
  double curvature_rel = 1e-6;  ///< G2: |kappa_r - kappa_l| <= curvature_rel * max(|kappa_l|, |kappa_r|)
};
/// InputError unless 0 <= angle_deg < 180 and 0 <= curvature_rel <= 1 (finite).
void validate(const ContinuityTolerances& t);

/// A joint between segments i-1 and i (i = 1..N-1).
struct Joint {
  int index = 0;          ///< i: the joint starts segment i
  double knot = 0;        ///< parameter value
  int multiplicity = 0;   ///< knot multiplicity
  int continuity = 0;     ///< C^k with k = d - multiplicity (from the knots alone)
  double kappa_left = 0;  ///< curvature at the end of segment i-1 (certified, kKappaRelError; NaN at a zero tangent)
  double kappa_right = 0; ///< curvature at the start of segment i
  int jump = 0;           ///< exact sign of kappa_right - kappa_left (0 where C^2 or at a zero tangent)
  bool zero_tangent = false;  ///< an end tangent is exactly zero: G1 and G2 fail
  bool pole = false;          ///< W = 0 at the knot (both segments have a pole there): kappas and angle NaN, jump 0, G1 and G2 fail
  double angle_deg = 0;   ///< angle between the end tangents (0 where C^1 by the knots); NaN at a zero tangent
  bool g1 = false;        ///< tangent directions agree within ContinuityTolerances::angle_deg
  bool g2 = false;        ///< G1 and curvature equal (exactly, or within curvature_rel)
};

/// "up", "down" or "none" for a jump sign.
inline const char* jump_name(int jump) { return jump > 0 ? "up" : jump < 0 ? "down" : "none"; }
/// The jump the JSON's `jump` and the pages show: none at a G2 joint (equal
/// curvature within ContinuityTolerances::curvature_rel, the same tolerance
/// that makes it G2), else the exact sign. The verdicts use the exact sign
/// (Joint::jump, `exact_jump` in the JSON); docs/semantics.md.
inline int shown_jump(const Joint& j) { return j.g2 ? 0 : j.jump; }

struct AnalyzeOptions {
  ClassifyOptions classify;    ///< depth D and Algorithm 2 on/off
  std::optional<int> split;    ///< joint s for the split verdict
  Mode split_mode = Mode::cmrwi;  ///< also the mode of the alternation verdict
  ContinuityTolerances continuity;  ///< G1/G2 tests at joints
  std::optional<SegmentRange> segments;  ///< judge only these segments (all when empty)
  std::vector<int> splits;               ///< joints s_1 < ... < s_k for the alternation verdict
  /// The each-piece verdict instead of the alternation: the groups between
  /// `splits` (every joint of the range when empty) each monotone on its own.
  bool each_piece = false;
};

struct SplineAnalysis {
  std::vector<SegmentClass> segments;  ///< Algorithms 1 and 2 as the paper states them
  std::vector<SegmentShape> shapes;    ///< exact straight / cusp / inflection facts, one per segment
  std::vector<Joint> joints;
  /// A closed spline's seam (joint N: the end of segment N-1 against the
  /// start of segment 0). With the whole period judged and no split joints,
  /// it is judged like every other joint (README, "Semantics").
  std::optional<Joint> seam;
  Direction cmrwi = Direction::undecided;
  Direction cmr = Direction::undecided;             ///< exact inflections (see above)
  Direction cmr_algorithm2 = Direction::undecided;  ///< the paper's Algorithm 2: what regions draw
  bool cusp = false;                                ///< some segment has a cusp: no finite curvature range
  bool pole = false;                                ///< some segment has a pole (SegmentShape::pole)
  std::optional<Split> split;
  std::vector<int> joint_conflicts;  ///< joints whose curvature jump goes against the verdict
  int exact_segments = 0;            ///< segments that needed the exact path
  SegmentRange range;                ///< the segments judged; the others' classes are left default
  std::optional<Alternation> alternation;  ///< with options.splits
  std::optional<EachPiece> each_piece;     ///< with options.each_piece
  std::vector<int> cuts;                   ///< the groups' cut joints (options.splits, or each_piece_cuts)
  std::vector<Direction> groups;           ///< with options.splits or each_piece: each group's verdict
  bool judged(int segment) const { return segment >= range.first && segment <= range.last; }
};

/// Validates options.split, .segments and .splits (InputError: "split 5 is
/// outside 1..2"); split and splits together are an error.
SplineAnalysis analyze(const BSpline& spline, const AnalyzeOptions& options = {});

/// The per-span work of analyze(), supplied by the caller (RegionMemo,
/// region/region_memo.hpp, remembers it between splines that differ in a
/// few points). Each must return exactly what segment_shape, classify_segment
/// and joint_between return for the same arguments; analyze(spline, options,
/// parts) then equals analyze(spline, options).
struct AnalyzeParts {
  std::function<SegmentShape(const BSpline&, const Segment&)> shape;
  std::function<SegmentClass(const BSpline&, const Segment&, const ClassifyOptions&)> classify;
  std::function<Joint(const BSpline&, int left, int right, const ContinuityTolerances&)> joint;
};
SplineAnalysis analyze(const BSpline& spline, const AnalyzeOptions& options, const AnalyzeParts& parts);

/// analyze(spline, options, parts) in three steps, for a caller that runs
/// the spans on several threads and streams them (report/analyze_json.hpp):
/// start_analysis validates the options (the errors of analyze) and sizes
/// segments, shapes and joints; analyze_span(i) fills segment i's shape and
/// class and, for i > 0, joints[i-1] (the spans are independent: any order,
/// any threads, given parts that are safe to call concurrently, as the
/// defaults are); finish_analysis adds the seam, the counts and the
/// verdicts. start, every span, finish: exactly analyze()'s result.
SplineAnalysis start_analysis(const BSpline& spline, const AnalyzeOptions& options);
void analyze_span(SplineAnalysis& analysis, const BSpline& spline, const AnalyzeOptions& options,
                  const AnalyzeParts& parts, int i);
void finish_analysis(SplineAnalysis& analysis, const BSpline& spline, const AnalyzeOptions& options,
                     const AnalyzeParts& parts);
/// The default parts: segment_shape, classify_segment, joint_between.
AnalyzeParts default_analyze_parts();

/// analyze(spline, options) with the spans in chunks on `threads` threads
/// (0: every available core): the same result. `cancel` (may be null) is read
/// between chunks; once it is set no further chunk starts and Cancelled is
/// thrown (the Python module's KeyboardInterrupt).
SplineAnalysis analyze_on_threads(const BSpline& spline, const AnalyzeOptions& options, int threads = 0,
                                  const std::atomic<bool>* cancel = nullptr);

/// The verdict of segments [first, last) from their classes and the joints
/// strictly inside that range (joints[i-1] is the joint starting segment i).
Direction part_verdict(const std::vector<SegmentClass>& segments, const std::vector<Joint>& joints, int first,
                       int last, Mode mode, std::vector<int>* conflicts = nullptr);
Split combine_split(Direction before, Direction after);
/// A class part_verdict reads as nothing (constant, no inflection, curvature
/// sign 0): appended after the last segment, it puts a closed spline's seam
/// inside the part as the joint before it.
SegmentClass neutral_class();
/// The alternation verdict of consecutive groups' directions (segments.hpp).
Alternation alternation_verdict(const std::vector<Direction>& groups);
/// The each-piece verdict of the groups' directions (segments.hpp).
EachPiece each_piece_verdict(const std::vector<Direction>& groups);

/// The joint between segments `left` and `right` (right = left + 1, or for a
/// closed spline's seam left = N-1, right = 0: index N, knot at the end of the
/// period): continuity from the knots, certified curvatures, the exact jump
/// sign, and G1/G2 within `tolerances` (README, "Semantics").
Joint joint_between(const BSpline& spline, int left, int right, const ContinuityTolerances& tolerances);

/// Exact sign of kappa_right - kappa_left at a joint, from the spline's double
/// data (rational arithmetic).
int curvature_jump_sign(const BSpline& spline, const Segment& left, const Segment& right);

/// Curvature of segment s at its start (side 0) or end (side 1), certified:
/// exact sign, relative error at most kKappaRelError (error-bounded double
/// first, exact rationals where the bound is looser). NaN where the tangent
/// there is exactly zero.
double certified_end_curvature(const BSpline& spline, const Segment& s, int side);

/// The segment classes with Algorithm 2's inflection replaced by the exact
/// one of `shapes` (depth 0): what part_verdict judges for SplineAnalysis::cmr.
std::vector<SegmentClass> exact_inflection_classes(const std::vector<SegmentClass>& segments,
                                                   const std::vector<SegmentShape>& shapes);

}  // namespace cmr
