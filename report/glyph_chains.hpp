#pragma once
// Internal to cmr::report: the glyph fix's chain search (report/glyph_fix.cpp;
// docs/fix.md "Chains of smooth joints").
//
// With every node held, a contour under curvature-extrema-at-nodes and
// g2-at-smooth-nodes falls apart into small problems. Its *units* run from
// one explicit node to the next: a cubic segment (N0, H1, H2, N1), or a
// TrueType run of off-curve points between two on-curve points (N0, A, B,
// N1: two quadratic pieces (N0, A, M) and (M, B, N1) meeting at the
// implied node M = (A + B) / 2; a run of one off-curve point is one piece;
// of a run of three (A, B, C), B moves too, in a box of half the reach,
// and of four or more, the points next to the nodes are its handles and the
// inner ones are held). The extrema gate judges each piece on
// its own Bezier points; g2 judges a smooth joint from the end curvatures
// of its two sides, for a piece of degree d
//   k(0) = (d-1)/d det(b1 - b0, b2 - b1) / |b1 - b0|^3,
//   k(1) = (d-1)/d det(b_{d-1} - b_{d-2}, b_d - b_{d-1}) / |b_d - b_{d-1}|^3,
// and passes where |kl - kr| <= tol max(|kl|, |kr|). A unit's points shape
// its own pieces only (M is inside the unit), so the extrema checks and g2
// at implied nodes are a unit's own, and the cost (the total squared move
// from the source) is a sum over units. So the joints g2 does not judge
// (corners) cut the contour into chains, runs of units joined at smooth
// nodes, and each chain's nearest passing positions are a shortest path: a
// layer per unit, a state per candidate position of its points (H1, H2;
// A, B) that passes the unit's own checks, with its end curvatures k0, k1
// and its cost, and an edge between consecutive units' states where g2
// passes at their node. A candidate may make a corner smooth (its point
// next to the node within the gate's G1 angle of the line from the
// neighbour's point through the node: TeX Gyre Termes V's p17), and g2 then
// judges that node: there a candidate passes only where g2 does against
// the neighbouring unit's end curvature as it is at `at` (where that
// unit's chain moves too, the caller's whole judge decides).
//
// For kr > 0 g2 passes exactly when kl is in [kr (1 - tol), kr / (1 - tol)]
// (kl <= 0 would differ by at least max(|kl|, kr)); for kr < 0 the mirror
// image; for kr = 0 only kl = 0. Both ends of that interval rise with kr, so
// with the previous layer sorted by k1 and the next by k0 each state's best
// predecessor is a sliding-window minimum: O(N log N) for N states.
//
// Without the extrema gate every candidate passes it; with it, the extrema
// check of a candidate is Algorithm 1, exact (classify_bezier; a
// quadratic piece's its closed form, quadratic_monotone, the same verdict):
// monotone curvature (increasing, decreasing or constant) passes, anything
// else is left out. That is stricter than the gate, which also passes a
// piece with a cusp or a near-constant curvature, so the answer is the
// nearest among positions whose pieces are certified monotone, in the box
// searched, nodes held. The caller re-judges it on the whole gate. The end
// curvatures are computed as the gate computes them (c A / G / sqrt(G)),
// its values bit for bit on the grid. At an implied node both sides' G is
// the same leg's, so the two curvatures are in the ratio of two small
// integers and meet the tolerance exactly as often as not: g2 there is
// judged as the gate judges it. At an explicit node (a window bound in
// the shortest path) it is judged with a margin of 1e-6 of the tolerance
// (far above the doubles' rounding, far below a grid step's effect).
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "io/font.hpp"
#include "report/glyph_settle.hpp"
#include "report/report.hpp"
#include "spline/vec2.hpp"

namespace cmr::report::glyph_detail {

/// Whether point k of contour c may move: a source point (not a line's
/// added one) that `movable` lists.
bool may_move(const import::Contour& c, const std::vector<int>& movable, int k);

/// The interval of left curvatures kl that pass g2 (tolerance t) against
/// kr: [kr (1 - t), kr / (1 - t)] for kr > 0, the mirror image for kr < 0,
/// [0, 0] for kr = 0. Both ends rise with kr.
std::array<double, 2> passing_left(double kr, double t);

/// The box searched around where each handle is: a free handle every grid
/// position within kChainReach cells each way (17 x 17 positions), a smooth
/// node's handle kChainSlideReach grid steps each way along its tangent, the
/// middle point of a run of three half the reach each way (9 x 9; the fix's
/// box; a test's may be smaller).
inline constexpr int kChainReach = 8, kChainSlideReach = 48;
/// Units' passing states kept between chain searches of one contour with
/// one source, movable points, options, grid and max_move (the bowl
/// search's: a node move changes only the units at it). A unit's states
/// depend on its own points, its neighbours' points next to its nodes (its
/// nodes' smoothness and g2 links) and, where a neighbour is a line or
/// meets it at a corner, all of that neighbour's points, and on the box:
/// those are the key. Used by searches that hold every node
/// (node_reach 0) and are not probes.
class ChainCache {
 public:
  ChainCache();
  ~ChainCache();
  ChainCache(const ChainCache&) = delete;
  ChainCache& operator=(const ChainCache&) = delete;
  struct Impl;
  std::unique_ptr<Impl> impl;
};
struct ChainBox {
  int reach = kChainReach;
  int slide_reach = kChainSlideReach;
  int node_reach = 0;  ///< a smooth node inside a chain moves too, with its handles, this many cells each way
  bool every_stuck = false;  ///< find every unit with no passing position (ChainResult::stuck), not a chain's first
  /// A probe (the bowl search's): only the units that start or end at this
  /// node are searched, each up to its first passing position, and no chain
  /// is answered: ChainResult::stuck lists those of them with none (-1: a
  /// search).
  int probe_node = -1;
  bool probe_ranges = false;  ///< with probe_node: every passing position, their ranges in ChainResult::ranges
  ChainCache* cache = nullptr;  ///< where units' states are kept between searches (none: computed each time)
  int stride = 1;  ///< a free handle's box takes every stride-th cell each way (the bowl search's widest: 2)
};
/// The end curvatures of a unit's passing positions in a box: k0 at its
/// start node, k1 at its end node, each from lo to hi.
struct CurvatureRange {
  int start = 0, end = 0;     ///< the unit's nodes
  bool linked_start = false;  ///< g2 judges its start node (the unit before it is in its chain)
  double k0_lo = 0, k0_hi = 0, k1_lo = 0, k1_hi = 0;
};
/// How far a node moves where the fix moves nodes in the chain search (the
/// growing search's node rounds, a cubic contour's second chain search, the
/// settling's node rounds): a cell each way, so a unit's candidates grow at
/// most 81 times.
inline constexpr int kChainNodeReach = 1;
/// The settling's box (glyph_fix.cpp, settle: every chain, each time the
/// fix moves): 9 x 9 cells a free handle, 49 steps a sliding one.
inline constexpr ChainBox kChainSettleBox{4, 24};

/// The chain search's work, in ticks of a unit (Work): a cubic piece judged
/// (end curvatures and Algorithm 1) an eighth of a unit, a quadratic one
/// (end curvatures and quadratic_monotone) or a candidate that the end
/// curvatures reject before any piece is judged a 64th. So a unit takes
/// about as long as one of the other searches' (1.5-4.5 us on the project's
/// VM): charged a unit each, the chain search's took 0.17 us (cubic) and
/// 0.2-0.3 us (quadratic; before the closed form).
inline constexpr long kTicksPerUnit = 512, kCubicPieceTicks = 64, kQuadraticPieceTicks = 8, kRejectTicks = 8;

/// Whether the quadratic Bezier piece (b0, b1, b2) has monotone curvature
/// (Algorithm 1's verdict: increasing, decreasing or constant), in closed
/// form. With a = b1 - b0, b = b2 - b1 and c = b - a, P'(t) = 2 (a + t c)
/// and P'' = 2 c, so det(P', P'') = 4 det(a, b) is constant, P''' = 0 and
/// lambda = -3 det(P', P'') (P' . P'') has degree 4n - 7 = 1: its Bernstein
/// coefficients are -48 det(a, b) (a . c) and -48 det(a, b) (b . c). So the
/// curvature is monotone exactly where det(a, b) = 0 or a . c and b . c are
/// not of strictly opposite signs. Exact where every coordinate is a
/// half-integer below 2^20 in magnitude (grid 1: the nodes and off-curve
/// points, and the implied nodes between them); nullopt elsewhere (the
/// caller asks Algorithm 1).
std::optional<bool> quadratic_monotone(Vec2 b0, Vec2 b1, Vec2 b2);

/// The chain search from `at` (the contour's distinct points; `src` the
/// source's): each chain that holds a violation of `o` at `at` (`every`:
/// each chain) is replaced by its nearest passing handle positions (a
/// TrueType unit's off-curve points are its handles) in `box`
/// around `at` (nodes held; handles that `movable` leaves out, or a line's,
/// held too), where it has one. A contour smooth all round is one chain
/// that closes on itself: each candidate of its unit with the fewest in
/// turn, the shortest path from it closed by g2 at that unit's start (P052
/// O: 2 paths where unit 0 had 655); searched
/// only with `every` (the settling of a fix: from the source, its answer
/// led the searches after it to farther fixes, as on Nimbus Sans b, d and
/// q's counters). Applies where `o` has only curvature-extrema-at-nodes and
/// g2-at-smooth-nodes and the contour is a closed polynomial cubic or
/// quadratic with an explicit node; nullopt elsewhere. Work: as
/// kTicksPerUnit says per candidate of a unit, and a unit per unit of each
/// path of a closed chain; where it runs out, no chain is answered.
/// `all_or_none`: where one chain has no answer none is answered, and the
/// search ends at the first failing unit with no passing position (the
/// failing units with fewer free points first).
///
/// Nodes that move (box.node_reach > 0, the nodes `moving_nodes` lists; on
/// a contour with a corner, not one smooth all round, whose closing path
/// is searched once per state of its first unit): such a node inside a
/// chain (g2 judges it), exactly smooth, movable with
/// both its handles and between two units of two or more free points takes
/// each grid translation within node_reach cells each way, its two handles
/// with it (so it stays exactly smooth: the paper's rigid group), and each
/// of its handles' boxes and slides move with it. A state of a unit is then
/// also its start and end nodes' translations, its cost the start node's
/// squared move too (each node counted once along the chain), and an edge
/// joins two states only where they put their shared node in the same
/// place; the shortest path is taken per translation (the window of
/// advance() within one translation's states). So the answer is the
/// nearest in the box with those nodes in their boxes too, the others held.
/// Each translation multiplies a unit's candidates: (2 node_reach + 1)^2
/// per moving node.
struct ChainResult {
  std::vector<Vec2> points;  ///< `at` with every chain answered moved to its answer
  int chains = 0;            ///< the chains searched: those failing at `at` (every one with `every`)
  int solved = 0;            ///< of those, the chains with an answer (all: every chain passes as above)
  double cost = 0;           ///< the answers' cost: their points' total squared move from `src` (held nodes aside)
  std::vector<int> stuck;    ///< the nodes of each unit found with no passing position in the box
  bool searched = true;      ///< false: asked to move nodes (node_reach > 0) where none may, nothing searched
  /// The end curvatures' ranges of each unit whose passing positions were
  /// found (the whole search: every unit of the chains searched that has
  /// some; a probe: only with probe_ranges).
  std::vector<CurvatureRange> ranges;
  std::vector<int> unanswered;  ///< the nodes of the units of each chain searched and left without an answer
};
std::optional<ChainResult> chain_search(const import::Contour& c, const std::vector<Vec2>& src,
                                        const std::vector<Vec2>& at, const std::vector<int>& movable,
                                        const ReportOptions& o, double grid, double max_move, Work& work,
                                        const ChainBox& box = {}, bool every = false, bool all_or_none = false,
                                        const std::vector<int>& moving_nodes = {});

/// The chain search with a growing box: from the source `src`, boxes of
/// reach 8, 16 and 24 cells (a slide 6 grid steps a cell each way), each
/// searching only the chains that still fail where the one before left the
/// contour, all_or_none (only an answer to every chain is used). Where a
/// box of 24 cells leaves a chain unanswered with a unit that no position
/// passes (its nodes held), boxes of 16 and 24 cells again with the nodes
/// of every such unit found moving too (kChainNodeReach cells each way),
/// each box again while it finds another such unit, and none where none of
/// those nodes may move (ChainResult::searched). A box of 8 cells with nodes moving took Noto
/// Sans `Q`'s share of the work without an answer. Its answer where every
/// chain is answered (all: each passes as chain_search says, the other
/// nodes held); nullopt where none is, the work runs out, or the search
/// does not apply. Measured on the quadratic contours no other search
/// fixes under both type gates: Noto Serif `s` at 16 cells, `S` and `C` at
/// 24; Noto Sans `Q` with p9 moving, at 16 (its tail's short run p7, p8 has
/// no passing position with p9 held: p7 would have to be half a unit off
/// the grid).
inline constexpr std::array<int, 3> kGrowingReach{8, 16, 24};
inline constexpr std::array<int, 2> kGrowingNodeRoundReach{16, 24};
inline constexpr int kGrowingSlidePerCell = 6;
std::optional<std::vector<Vec2>> growing_chain_search(const import::Contour& c, const std::vector<Vec2>& src,
                                                      const std::vector<int>& movable, const ReportOptions& o,
                                                      double grid, double max_move, Work& work);

}  // namespace cmr::report::glyph_detail
