#pragma once
// Internal to cmr::report: the glyph fix's chain search (report/glyph_fix.cpp;
// docs/fix.md "Chains of smooth joints").
//
// With every node held, a cubic contour under curvature-extrema-at-nodes and
// g2-at-smooth-nodes falls apart into small problems. The extrema gate judges
// each segment on its own Bezier points (N0, H1, H2, N1). g2 judges a smooth
// joint from the end curvatures of its two sides,
//   k(0) = 2/3 det(H1 - N0, H2 - H1) / |H1 - N0|^3,
//   k(1) = 2/3 det(H2 - H1, N1 - H2) / |N1 - H2|^3,
// and passes where |kl - kr| <= tol max(|kl|, |kr|). Each handle shapes one
// segment only, and the cost (the total squared move from the source) is a
// sum over the handles. So the joints g2 does not judge (corners) cut the
// contour into chains, runs of segments joined at smooth joints, and each
// chain's nearest passing handle positions are a shortest path: a layer per
// segment, a state per candidate (H1, H2) of that segment that passes the
// extrema check, with its end curvatures k0, k1 and its cost, and an edge
// between consecutive segments' states where g2 passes at their joint.
//
// For kr > 0 g2 passes exactly when kl is in [kr (1 - tol), kr / (1 - tol)]
// (kl <= 0 would differ by at least max(|kl|, kr)); for kr < 0 the mirror
// image; for kr = 0 only kl = 0. Both ends of that interval rise with kr, so
// with the previous layer sorted by k1 and the next by k0 each state's best
// predecessor is a sliding-window minimum: O(N log N) for N states.
//
// Without the extrema gate every candidate passes it; with it, the extrema
// check of a candidate is Algorithm 1, exact (classify_bezier):
// monotone curvature (increasing, decreasing or constant) passes, anything
// else is left out. That is stricter than the gate, which also passes a
// piece with a cusp or a near-constant curvature, so the answer is the
// nearest among positions whose pieces are certified monotone, in the box
// searched, nodes held. The caller re-judges it on the whole gate. g2 is
// compared in doubles with a margin of 1e-6 of the tolerance (far above the
// error of the doubles' end curvatures, far below a grid step's effect).
#include <optional>
#include <vector>

#include "io/font.hpp"
#include "report/glyph_settle.hpp"
#include "report/report.hpp"
#include "spline/vec2.hpp"

namespace cmr::report::glyph_detail {

/// The box searched around where each handle is: a free handle every grid
/// position within kChainReach cells each way (17 x 17 positions), a smooth
/// node's handle kChainSlideReach grid steps each way along its tangent (the
/// fix's box; a test's may be smaller).
inline constexpr int kChainReach = 8, kChainSlideReach = 48;
struct ChainBox {
  int reach = kChainReach;
  int slide_reach = kChainSlideReach;
};
/// The settling's box (glyph_fix.cpp, settle: every chain, each time the
/// fix moves): 9 x 9 cells a free handle, 49 steps a sliding one.
inline constexpr ChainBox kChainSettleBox{4, 24};

/// The chain search from `at` (the contour's distinct points; `src` the
/// source's): each chain that holds a violation of `o` at `at` (`every`:
/// each chain) is replaced by its nearest passing handle positions in `box`
/// around `at` (nodes held; handles that `movable` leaves out, or a line's,
/// held too), where it has one. A contour smooth all round is one chain
/// that closes on itself: each candidate of its first segment in turn, the
/// shortest path from it closed by g2 at that segment's start; searched
/// only with `every` (the settling of a fix: from the source, its answer
/// led the searches after it to farther fixes, as on Nimbus Sans b, d and
/// q's counters). Applies where `o` has only curvature-extrema-at-nodes and
/// g2-at-smooth-nodes and the contour is a closed polynomial cubic; nullopt
/// elsewhere. Work: one
/// unit per candidate classified (and per segment of each path of a closed
/// chain); where it runs out, no chain is answered.
struct ChainResult {
  std::vector<Vec2> points;  ///< `at` with every chain answered moved to its answer
  int chains = 0;            ///< the chains searched: those failing at `at` (every one with `every`)
  int solved = 0;            ///< of those, the chains with an answer (all: every chain passes as above)
  double cost = 0;           ///< the answers' cost: their handles' total squared move from `src`
};
std::optional<ChainResult> chain_search(const import::Contour& c, const std::vector<Vec2>& src,
                                        const std::vector<Vec2>& at, const std::vector<int>& movable,
                                        const ReportOptions& o, double grid, double max_move, Work& work,
                                        const ChainBox& box = {}, bool every = false);

}  // namespace cmr::report::glyph_detail
