#pragma once
// Internal to cmr::design and the libraries above it: a library user includes
// `design/fix.hpp` or `design/kcurve.hpp` (space curves:
// `design/space_fix.hpp`).
// A certified fix on a grid (`cmr fix FONT.ufo`, docs/fix.md "On the
// font's grid"): the nearest set of grid positions near a fix whose exact
// judging passes.
//
//   snap_to_grid(original, fix, judge, options) -> GridFix
//
// A fix (design/fix.hpp) puts its points on the boundary of the passing
// region, so rounding each coordinate to the grid drops it back out about
// half the time. Here every moved unit gets candidate grid positions and the
// combinations are tried in order of their total squared displacement from
// the original points, each judged by `judge` (the caller's exact judge:
// violations, 0 when it passes); the first that passes is the answer, so
// among the candidates it is the nearest. The units, read off the fix's
// moves:
//  * a rigid group (a node moved with its handles by one displacement, the
//    paper's group that keeps G1): integer multiples of the grid as one
//    translation, so every tangent direction stays exactly the same;
//  * a slide (a handle moved along the line through its unmoved node, which
//    keeps G1): the grid points exactly on that line, node + k * (primitive
//    direction), where the node and the direction are on the grid (a line
//    with no other grid point near keeps the handle where it is);
//  * a free point: the grid points around it.
// Partners (GridOptions::partners: points the fix left alone, typically the
// neighbouring handles) are units too, moving a few grid steps from where
// they are: a slide on their smooth node's tangent, else free.
// Candidates of a unit are the grid positions within `radius` cells of its
// off-grid target (and its original position); the radius grows (1, 2, 4,
// 8 cells) until a passing combination is found, the product of candidate
// counts is capped at kMaxCombinations (the radius of each unit shrinks to
// fit), and the judge is called at most max_evaluations times. Points are
// on the grid when the input's are: a coordinate c is on it when c / grid is
// an integer.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "design/fix.hpp"

namespace cmr {

struct GridOptions {
  double grid = 1;            ///< the grid step (font units: 1)
  double max_move = 0;        ///< largest displacement of a point; 0: none beyond the search's own
  long max_evaluations = 20000;
  double max_seconds = 20;
  /// max_seconds counts the calling thread's CPU time (spline/cpu_clock.hpp),
  /// not the wall clock: the same answer on a loaded machine.
  bool thread_cpu_clock = false;
  /// Points the fix did not move that may move too, each by a few grid
  /// steps (a narrow passing region often holds no grid point for the moved
  /// units alone: a neighbouring handle's step opens it); in order of
  /// preference, at most max_partners of them.
  std::vector<int> partners;
  int max_partners = 3;
};

/// Combinations tried per radius at most.
inline constexpr long kMaxCombinations = 200000;

struct GridFix {
  bool found = false;
  std::string reason;              ///< why not (one line)
  std::optional<BSpline> spline;   ///< the fixed spline on the grid (found)
  std::vector<PointMove> moves;    ///< every moved point, to grid positions
  double total_squared = 0, max_distance = 0;
  double off_grid_max_distance = 0;  ///< the off-grid fix's largest move (for the "nearest off-grid" line)
  long evaluations = 0;
  long combinations = 0;  ///< candidate combinations formed and ordered (the snap's work besides the judge)
};

/// The nearest on-grid positions for the units `fix` moved (see above),
/// judged by `judge` (thread-safe not needed: called on this thread).
GridFix snap_to_grid(const BSpline& original, const FixResult& fix, const std::function<int(const BSpline&)>& judge,
                     const GridOptions& options);

}  // namespace cmr
