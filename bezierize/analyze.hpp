#pragma once
// Spline-level verdicts over all segments (CAD&A 2024 §4.2).
//
//  * CMRWI: every segment monotone in one common direction (constant, i.e.
//    straight, segments go with either); at a joint where the spline is not
//    C^2 (knot multiplicity >= d-1, so curvature may jump) the jump must go the
//    same way. If every segment is constant the verdict follows Algorithm 1's
//    rule order (condition (1) first): increasing.
//  * CMR: CMRWI and no inflection: Algorithm 2 finds none in any segment and
//    the curvature has one sign throughout (a sign change at a joint is an
//    inflection too).
//  * Split at joint s (1 <= s <= N-1): segments 0..s-1 against s..N-1, each
//    part judged as above (in CMRWI or CMR mode); the jump at joint s itself is
//    free. inc-dec puts a curvature maximum at the joint, dec-inc a minimum.
// Verdicts: a part that is not monotone makes "none"; otherwise one that is
// undecided (depth limit) makes "undecided".
//  * Segment control (bezierize/segments.hpp): with options.segments only
//    those segments are classified and judged (the verdicts above, the split
//    and the joint conflicts are of that range); with options.splits the
//    range's groups between the joints get the alternation verdict.
#include <optional>
#include <string>
#include <vector>

#include "bezierize/classify.hpp"
#include "bezierize/segments.hpp"
#include "spline/bspline.hpp"

namespace cmr {

enum class Direction : std::uint8_t { increasing, decreasing, none, undecided };
enum class Split : std::uint8_t { inc_inc, inc_dec, dec_inc, dec_dec, none, undecided };
enum class Mode : std::uint8_t { cmrwi, cmr };

const char* to_string(Direction d);
const char* to_string(Split s);

/// A joint between segments i-1 and i (i = 1..N-1).
struct Joint {
  int index = 0;          ///< i: the joint starts segment i
  double knot = 0;        ///< parameter value
  int multiplicity = 0;   ///< knot multiplicity
  int continuity = 0;     ///< C^k with k = d - multiplicity
  double kappa_left = 0;  ///< curvature at the end of segment i-1
  double kappa_right = 0; ///< curvature at the start of segment i
  int jump = 0;           ///< exact sign of kappa_right - kappa_left (0 where C^2)
};

struct AnalyzeOptions {
  ClassifyOptions classify;    ///< depth D and Algorithm 2 on/off
  std::optional<int> split;    ///< joint s for the split verdict
  Mode split_mode = Mode::cmrwi;  ///< also the mode of the alternation verdict
  std::optional<SegmentRange> segments;  ///< judge only these segments (all when empty)
  std::vector<int> splits;               ///< joints s_1 < ... < s_k for the alternation verdict
};

struct SplineAnalysis {
  std::vector<SegmentClass> segments;
  std::vector<Joint> joints;
  Direction cmrwi = Direction::undecided;
  Direction cmr = Direction::undecided;
  std::optional<Split> split;
  std::vector<int> joint_conflicts;  ///< joints whose curvature jump goes against the verdict
  int exact_segments = 0;            ///< segments that needed the exact path
  SegmentRange range;                ///< the segments judged; the others' classes are left default
  std::optional<Alternation> alternation;  ///< with options.splits
  std::vector<Direction> groups;           ///< with options.splits: each group's verdict
  bool judged(int segment) const { return segment >= range.first && segment <= range.last; }
};

/// Validates options.split, .segments and .splits (InputError: "split 5 is
/// outside 1..2"); split and splits together are an error.
SplineAnalysis analyze(const BSpline& spline, const AnalyzeOptions& options = {});

/// The verdict of segments [first, last) from their classes and the joints
/// strictly inside that range (joints[i-1] is the joint starting segment i).
Direction part_verdict(const std::vector<SegmentClass>& segments, const std::vector<Joint>& joints, int first,
                       int last, Mode mode, std::vector<int>* conflicts = nullptr);
Split combine_split(Direction before, Direction after);
/// The alternation verdict of consecutive groups' directions (segments.hpp).
Alternation alternation_verdict(const std::vector<Direction>& groups);

/// Exact sign of kappa_right - kappa_left at a joint, from the spline's double
/// data (rational arithmetic).
int curvature_jump_sign(const BSpline& spline, const Segment& left, const Segment& right);

}  // namespace cmr
