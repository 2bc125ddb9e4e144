#pragma once
// Internal to cmr::report: the glyph fix's bowl search (report/glyph_fix.cpp;
// docs/fix.md "Round bowls"), which moves a cubic contour's nodes where the
// chain search (report/glyph_chains.hpp) finds no answer with them held.
#include <array>
#include <optional>
#include <vector>

#include "io/font.hpp"
#include "report/glyph_chains.hpp"
#include "report/glyph_settle.hpp"
#include "report/report.hpp"
#include "spline/vec2.hpp"

namespace cmr::report::glyph_detail {

/// The bowl search (cubic contours). Where a unit has no passing handle
/// position with its nodes where they are (ChainResult::stuck): a quarter
/// arc between perpendicular tangents that spans a square or nearly so has
/// none at all (tests/report/quarter_arc_check.py), as in URW Gothic's O.
/// For the first stuck unit where one does, one of its two nodes moves
/// along its normal (the primitive grid vector square to the unit's handle
/// there, so the arc spans a less square box), its two handles with it, 1,
/// 2, ..., kBowlNormalReach grid steps each way (at most kBowlNormalReach
/// grid units), nearest first, to the first place where that unit has a
/// passing position and fewer units have none, both in the probe box
/// (handles sliding kBowlProbeSlide steps). A move changes only the two
/// units at the moved node, so a try probes those two, each up to its first
/// passing position (ChainBox::probe_node), and the other units' count is
/// the one before the move (every stuck unit counted: ChainBox::every_stuck).
/// Moves that leave a sharp end against a flat one are tried only where no
/// other unsticks the unit: a quarter arc is sharper at the end whose
/// tangent is square to its longer extent (with n1 - n0 = a t0 + b t1,
/// |a| |t0| against |b| |t1|; an ellipse's quarter is sharpest at the major
/// axis' end), and g2 at a smooth node between a unit sharper there and one
/// flatter there (one not stuck) fails on round shapes (URW Gothic d's
/// counter: top quarters made wider, bottom ones taller). Then the chain
/// search (the default box, nodes held) runs again from there, and so on
/// while a unit is stuck, up to kBowlNodeMoves moves. A node moves where it
/// is movable with both neighbours (handles), within max_move of the
/// source.
///
/// Where no unit is stuck and a chain is still unanswered, g2 fails between
/// units that each have passing positions. Where the end curvatures that
/// two units reach at their smooth node (ChainResult::ranges, over their
/// passing positions in the probe box) cannot meet g2 there, a gap, and all
/// four of their nodes are exactly smooth (every handle slides; a free
/// handle's wider box, below, may close a gap: URW Gothic a's and g's
/// bowls, lost where nodes moved first), a node of those two units moves
/// along its normal, 1 to kBowlGapReach grid steps each way, nearest first,
/// to the first place where both units at the moved node have passing
/// positions and fewer nodes have such a gap (their ranges probed:
/// ChainBox::probe_ranges; the others' as before the move); then the chain
/// search again, within the same kBowlNodeMoves moves. URW Bookman O: its
/// top-right quarter, taller than wide, is sharp at the top, where the
/// top-left one, wider than tall, is flat; the right side moves out. A gap
/// is sure to fail (no pair of positions meets g2 there); ranges that meet
/// may still fail, since a unit's k0 and k1 go together.
///
/// Where that leaves a chain unanswered, or no move unsticks a unit, the
/// chain search runs again with wider boxes for the free handles
/// (kBowlWideBoxes: reach, stride), each in turn: URW Gothic a and g, whose
/// bowls end at corners, need the end units' free handles some 20 units
/// away, and s a spine unit's (its nodes not exactly smooth, so its handles
/// free). The boxes of 16 and 24 cells take every other cell each way, a
/// sixteenth of a two-free-handle unit's candidates (taking every cell, 16
/// cells took 2.35 M work on P052 p); the settling after the bowl search
/// moves its answer on, cell by cell, to nearer passing positions. A contour
/// smooth all round is searched as one chain closing on itself (`every`).
///
/// Last, where no unit is stuck and no wider box answers: one rigid node of
/// an unanswered chain (ChainResult::unanswered) moved along its normal, 1
/// to kBowlGapReach grid steps each way, nearest first (every such node at
/// a step before the next step), each try judged by the chain search itself
/// (the default box; the units away from the moved node kept from the
/// searches before: ChainCache), the first that answers every chain taken.
/// Ranges that meet can still fail, since a unit's k0 and k1 go together:
/// P052 O, after a gap move at p3, is answered with p6 moved 6 steps in,
/// and P052 e with p21 moved 5 steps. The stages before it get three
/// quarters of `work`'s budget (the caller hands over a third of the
/// contour's), the last resort all of it.
/// `kept`: the units' states of the caller's chain search in the default
/// box (ChainCache: the same source, movable points, options, grid and
/// max_move), taken and added to by the bowl's searches in that box: its
/// first search, from where the caller's left the contour, computes only
/// the units that search moved or did not reach (URW Gothic a, s and g:
/// 4,700, 38,600 and 34,500 work units less, 6 to 18 % of the bowl's).
/// Its answer where every chain is answered (each passes as chain_search
/// says, with the nodes moved); nullopt where none is or the work runs out.
/// A local search: it moves the first stuck unit's nearest node that
/// unsticks it, not the nearest set of nodes.
inline constexpr int kBowlNormalReach = 16, kBowlNodeMoves = 8, kBowlProbeSlide = 24;
inline constexpr std::array<std::array<int, 2>, 3> kBowlWideBoxes{{{12, 1}, {16, 2}, {24, 2}}};  // reach, stride
inline constexpr int kBowlGapReach = 32;
std::optional<std::vector<Vec2>> bowl_search(const import::Contour& c, const std::vector<Vec2>& src,
                                             const std::vector<Vec2>& start, const std::vector<int>& movable,
                                             const ReportOptions& o, double grid, double max_move, Work& work,
                                             ChainCache& kept);

}  // namespace cmr::report::glyph_detail
