#pragma once
/// Nodes added where the moves find no fix of a glyph (`cmr fix FONT.ufo
/// --glyph G --require ... --add-nodes`, docs/fix.md "Adding nodes").
///
/// Where the glyph fix (report/glyph_fix.hpp) leaves a cubic contour
/// unfixed, its failing source cubics (never a line, never a quadratic)
/// are split:
///  - at each curvature extremum inside a segment (the extremum gate's
///    violation, at its local parameter t, 0.02 < t < 0.98): the new node
///    sits where the curvature peaks, so each piece can be monotone (URW
///    Gothic `b`'s counter peaks between all five of its nodes, and no
///    search of moves finds a fix);
///  - at t = 1/2 only, a cubic at a smooth line-to-curve join that fails
///    g2-at-smooth-nodes: the curvature must rise from the line's 0, and one
///    cubic whose far node is square to the line cannot (glyph_joins.hpp,
///    square_cubic_line_join), two can; where the glyph is not fixed so,
///    the caller tries again with two nodes there, at 1/3 and 2/3 (three
///    pieces: Nimbus Sans `D`'s counter and TeX Gyre Heros `D`'s, whose
///    bowls meet the stem square, are fixed only so).
/// A split is de Casteljau's (the same curve): on segment B0 B1 B2 B3 at
/// t, with L(a, b) = a + t (b - a): P01 = L(B0, B1), P12 = L(B1, B2),
/// P23 = L(B2, B3), Q = L(P01, P12), R = L(P12, P23), S = L(Q, R) = B(t);
/// the pieces are B0 P01 Q S and S R P23 B3 (B1' = P01, B2' = P23). Several
/// t in one segment split the right piece again at (t' - t) / (1 - t).
/// On the grid (step G): each new node S lands on one of the 9 grid points
/// around B(t) and its Q, R on S -/+ whole multiples a, b >= 1 of a
/// primitive grid vector v (|v_x|, |v_y| <= 40 cells), the choice with the
/// least |S'-S|^2 + |Q'-Q|^2 + |R'-R|^2: exactly smooth (Q, S, R collinear
/// in integers), written type="curve" smooth="yes". B1' and B2' keep their
/// nodes as they were: at an exactly smooth node both its handles are laid
/// again the same way with the node held (the other handle wanted where it
/// is), so a tangent whose primitive vector is long, e.g. (-43, 44), turns
/// to a nearby short one that lets the handle shorten; at a node smooth
/// with a line the handle stays on the line's direction (a whole multiple,
/// at least one, of its primitive vector); at a corner it is rounded. The
/// glyph with the nodes added is then fixed as any glyph (moves only; the
/// new points move as the source's do).
#include <optional>
#include <string>
#include <vector>

#include "io/ufo.hpp"
#include "report/glyph_fix.hpp"

namespace cmr::report {

struct AddedNode {
  int contour = 0;      ///< Contour::index
  std::string segment;  ///< the source segment it splits, by its nodes: "b/c1/p0-p3"
  double t = 0;         ///< where on that segment (0..1, before the grid)
  std::string why;      ///< "a curvature extremum" or "a line's smooth join"
  int point = 0;        ///< its index in the written contour
  Vec2 at{0.0};         ///< where the split puts it on the grid (before the fix moves it)
};

struct NodesAdded {
  std::string text;     ///< the .glif's text with the nodes added (import::rewrite_glif_points)
  import::Glyph glyph;  ///< read from `text` (its source: the source's .glif)
  std::vector<AddedNode> nodes;
  /// Per contour (the .glif's order), per point of `text`: the source point
  /// it is, or -1 for an added one.
  std::vector<std::vector<int>> source_point;
  /// Per contour, per source point: its position in the source.
  std::vector<std::vector<import::NewPoint>> source;
};

/// The glyph `g` (read from `text`, its .glif) with nodes added to each
/// contour `fixes` leaves unfixed (not already passing, not untouched), as
/// above, with `join_nodes` (1 or 2) nodes in each cubic of a failing line
/// join; nullopt where none of them has a segment to split (a quadratic
/// contour, or no violation of those two kinds). `options.grid` > 0.
std::optional<NodesAdded> add_nodes(const import::Glyph& g, const std::string& text,
                                    const std::vector<ContourFix>& fixes, const GlyphFixOptions& options,
                                    int join_nodes = 1);
/// Whether `added` has a node at a line's join (one that two nodes there might replace).
bool splits_a_join(const NodesAdded& added);

/// The source .glif's edits for a fix of `added.glyph` whose edits (of
/// `added.text`'s points) are `edits`: each source point that ends away
/// from its source position moves, and the added points come after the
/// point before them, at their final positions.
std::vector<import::PointEdit> source_edits(const NodesAdded& added, const std::vector<import::PointEdit>& edits);

}  // namespace cmr::report
