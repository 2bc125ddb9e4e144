#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
// Segment control (issue 11, item 2): which segments are judged, and several
// joints at once for curvature extrema.
//
//  * A SegmentRange first..last (inclusive span indices) restricts every
//    verdict to those segments: the others are not classified ("ignored"), and
//    the joints at the range's ends, like every joint outside it, play no part.
//  * Cut joints s_1 < ... < s_k, each strictly inside the range
//    (first < s_i <= last), group the judged segments into
//    [first, s_1), [s_1, s_2), ..., [s_k, last + 1).
//  * The alternation verdict of the groups (several joints at once, the
//    designer's "a curvature extremum at each given joint and nowhere else"):
//    every group is monotone (cmr::part_verdict in CMRWI or CMR mode) and
//    consecutive groups go opposite ways. Then the curvature is monotone
//    between the joints and turns at each of them: with group 0 increasing,
//    a maximum at s_1, a minimum at s_2, and so on. The jump at a cut joint
//    itself is free (either way, the extremum stays at the joint).
//    Precedence: a group that is not monotone, or two consecutive groups that
//    are certainly monotone the same way, make "fail" (no depth limit can
//    change that); otherwise an undecided group makes "undecided".
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "spline/fields.hpp"

namespace cmr {

/// Segments first..last (inclusive) are judged; the others are ignored.
struct SegmentRange {
  int first = 0;
  int last = 0;
  bool operator==(const SegmentRange&) const = default;
};

/// The verdict of several joints at once (see above).
/// Numbered as a region label (region.hpp: code(), 0 = fails).
enum class Alternation : std::uint8_t { fail = 0, first_increasing = 1, first_decreasing = 2, undecided = 3 };

/// "inc-first", "dec-first", "fail", "undecided".
const char* to_string(Alternation a);

/// The each-piece verdict (docs/semantics.md, "Each piece on its own"): every
/// group between the cut joints is monotone, each in either direction,
/// independently of its neighbours (no alternation, the jumps at the cut
/// joints free). A group that is not monotone makes "fail"; otherwise an
/// undecided one makes "undecided".
/// Numbered as a region label (region.hpp: code(), 0 = fails).
enum class EachPiece : std::uint8_t { fail = 0, monotone = 1, undecided = 2 };

/// "each-monotone", "fail", "undecided".
const char* to_string(EachPiece e);

/// The cut joints of the each-piece mode: `cuts` when given, else every joint
/// strictly inside the range (each piece its own group).
std::vector<int> each_piece_cuts(SegmentRange range, const std::vector<int>& cuts);

/// The range a request judges: `range` validated against a spline of
/// `segment_count` segments, or all of them when empty. InputError for
/// first > last or an index outside 0..N-1 ("segments 2..7: the curve has
/// segments 0..4").
SegmentRange judged_range(const std::optional<SegmentRange>& range, int segment_count);

/// Validates cut joints for a judged range: each strictly inside it
/// (range.first + 1 .. range.last) and strictly increasing; InputError that
/// names the joint otherwise ("split 5 is outside 1..3").
void validate_cuts(const std::vector<int>& cuts, SegmentRange range, int segment_count);

/// The groups [first, s_1), ..., [s_k, last + 1) as half-open index pairs.
std::vector<std::pair<int, int>> segment_groups(SegmentRange range, const std::vector<int>& cuts);

/// The group of segment `seg` (0 before s_1, 1 from s_1, ...); cuts sorted.
int group_of(const std::vector<int>& cuts, int seg);

/// Whether the curvature jump at joint `joint` (between segments joint-1 and
/// joint) counts in a verdict: the joint lies strictly inside the range
/// (both its segments judged) and is not a cut (a cut joint's jump is free).
bool joint_counts(SegmentRange range, const std::vector<int>& cuts, int joint);

/// "A..B" (two non-negative integers; A <= B is checked by judged_range) or
/// "A" (A..A); InputError naming `option` otherwise (a field, spline/fields.hpp,
/// or a program's own word for it).
SegmentRange parse_segment_range(const std::string& text, const std::string& option = field("segments"));

/// "S1,S2,..." (non-negative integers) or "" (no joints: every joint, for
/// each_piece); InputError naming `option` otherwise ("each_piece: expected
/// joints S1,S2,... (got 'x')"). The joints are validated later (validate_cuts).
std::vector<int> parse_joint_list(const std::string& text, const std::string& option = field("each_piece"));

}  // namespace cmr
