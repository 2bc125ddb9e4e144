#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
// The classifier: Algorithms 1 and 2 of Yoshida et al., CAD&A 21(1) 2024, §3,
// the reference every backend (CPU regions, the Vulkan shader) must match.
//
// Algorithm 1 (curvature monotonicity) on the Bernstein coefficients xi of
// lambda (bezierize/lambda.hpp), per (sub)segment:
//   (1) all xi >= 0          -> increasing
//   (2) all xi <= 0          -> decreasing      (both: lambda == 0, constant)
//   (3) xi_0 * xi_last < 0   -> not monotone
//   else split at t = 1/2 and decide both halves, depth first; level 0 is
//   the whole segment, pieces at level D are not split. (3) is checked
//   first. The rules, their certified form with uncertain signs, and the one
//   traversal every path uses are in bezierize/decide.hpp.
//   Halves in different directions -> not monotone; a piece undecided at
//   level D -> undecided (the paper counts it as not monotone; cmr keeps it
//   apart), unless another piece proves non-monotonicity.
// Algorithm 2 (inflection) on the coefficients nu of eta = det(P', P''):
//   (1) nu_0 * nu_last <= 0  -> inflection present
//   (2) all nu > 0 or all < 0 -> no inflection in this piece
//   else split as above; level D exhausted -> undecided.
//
// Exactness. Sign tests are exact comparisons with zero by design. The
// coefficients are first computed in double with a certified error bound
// (numeric/bounded.hpp); when a sign that matters is not certain, the span is
// recomputed in exact rational arithmetic from the double inputs (GMP), so the
// result is always the one Algorithms 1 and 2 give on exact coefficients.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bezierize/piece.hpp"
#include "spline/vec2.hpp"
#include "spline/bspline.hpp"
#include "spline/limits.hpp"

namespace cmr {

enum class Curvature : std::uint8_t { increasing, decreasing, non_monotone, undecided, constant };
enum class Inflection : std::uint8_t { none, present, undecided };

const char* to_string(Curvature c);
const char* to_string(Inflection i);

struct ClassifyOptions {
  int max_depth = kDefaultDepth;  ///< D: deepest subdivision level (level 0 = whole segment)
  bool inflection = true;  ///< also run Algorithm 2
};

struct MonotonicityResult {
  Curvature curvature = Curvature::undecided;
  int depth = 0;  ///< level at which it was decided (D when undecided)
};
struct InflectionResult {
  Inflection inflection = Inflection::undecided;
  int depth = 0;
  /// When inflection == none, the sign of eta (the curvature's sign); for a
  /// rational segment the sign of D, which is the curvature's sign times W's
  /// (SegmentShape::kappa_sign is the curvature's own); else 0.
  int kappa_sign = 0;
};

/// Folds Algorithm 1's pieces in depth-first order: a zero piece (lambda == 0)
/// or a non-monotone one stops with that answer; increasing and decreasing
/// pieces together mean not monotone; a piece still split at level D makes the
/// answer undecided unless a later piece proves non-monotonicity.
class MonotonicityFold {
 public:
  /// Returns true when the traversal can stop.
  bool visit(Piece p, int level);
  MonotonicityResult result(int max_depth) const;

 private:
  bool inc_ = false, dec_ = false, undecided_ = false;
  int deepest_ = 0;
  std::optional<MonotonicityResult> stop_;
};

/// Folds Algorithm 2's pieces: an inflection stops; pieces without one set
/// the depth; anything else (split at level D) makes the answer undecided.
class InflectionFold {
 public:
  bool visit(Piece p, int level);
  /// kappa_sign: the sign of eta at the start (the curvature's sign when
  /// there is no inflection).
  InflectionResult result(int max_depth, int kappa_sign) const;

 private:
  bool undecided_ = false;
  int deepest_ = 0;
  std::optional<InflectionResult> stop_;
};


struct SegmentClass {
  MonotonicityResult monotonicity;
  InflectionResult inflection;  ///< undecided at depth 0 when not requested
  bool exact_used = false;      ///< the exact fallback ran for this segment
};

/// Classifies a Bezier segment given by its control points (exact doubles).
/// InputError where a coordinate is not finite (the exact path has no
/// rational for it).
SegmentClass classify_bezier(std::span<const Vec2> points, const ClassifyOptions& options = {});
/// Classifies segment s of a B-spline; exactness is relative to the spline's
/// double knots and control points (the Bezier points are rounded, so the
/// exact path re-extracts them from the knots exactly).
SegmentClass classify_segment(const BSpline& spline, const Segment& s, const ClassifyOptions& options = {});

}  // namespace cmr
