#pragma once
// Internal to cmr::report: joins of a glyph's contour where no designer's
// move passes g2-at-smooth-nodes (with an extremum gate), found before the
// glyph fix searches (report/glyph_fix.cpp), so it says so at once.
#include <optional>
#include <string>
#include <vector>

#include "io/font.hpp"
#include "report/report.hpp"

namespace cmr::report::glyph_detail {

/// A quadratic contour's smooth joint between a straight piece (a line: it
/// holds an added point, which never moves) and a curve, where
/// g2-at-smooth-nodes is required: the curve's end curvature would have to
/// be 0 there, and a quadratic piece has that only when it is straight
/// itself (its three Bezier points collinear). Then the next piece would
/// meet it with the same jump, unless it is straight too, and so on along
/// the curved side up to the first joint where g2 does not apply (a corner)
/// or a line starts: a joint where that chain ends at a line's end (which
/// stays) off the line's own, so that the chain cannot be straight, is
/// such a joint, and no move of the source's points passes the gate there.
/// (Where the chain ends at a corner that may move, or on the line, a
/// straight chain would pass: flattening_g2_join.) Smooth nodes stay
/// smooth under the designer's moves, so g2 applies along the chain in any
/// fix as in the source; the tolerance must be below 1 (else g2 passes any
/// jump). The joint's name, or "" when there is none.
std::string unmovable_g2_join(const import::Contour& c, const ReportOptions& o);

/// The same join where the chain ends at a corner (which may move) or at a
/// line's end on J's line, or closes on itself: no move of the source's
/// points passes the gate there unless every piece of the chain is straight
/// on J's line (J and its line stay: a line's end node is held), so every
/// fix moves each of the chain's points onto that line, the farthest
/// (`point`) by at least `distance` (font units): it flattens the curve from
/// J to `far` (the corner or line end; "" where the chain closes on itself)
/// into the line rather than fixing it. Of several such joins the one with
/// the largest such move (the first of equals); nullopt where there is none.
struct FlatteningJoin {
  std::string join, far, point;
  double distance = 0;
};
std::optional<FlatteningJoin> flattening_g2_join(const import::Contour& c, const ReportOptions& o);

/// A cubic contour's smooth join J of a line and a curve piece S = (J, H1,
/// H2, F) under g2-at-smooth-nodes and an extremum gate (curvature-extrema-
/// at-nodes, or max-extrema-per-segment:0) together, where F is an exactly
/// smooth node whose tangent is square to the line: no move of the designer's
/// (report/contour_moves.hpp) passes both, so the search is not started.
/// The moves keep J (a line's end) and the line, H1 on the line (J stays
/// smooth, H1 never passes J), and F's tangent direction (F's group
/// translates, its handles slide), so g2 at J, which needs S's end
/// curvature exactly 0 (the line's), puts H2 where the two lines cross.
/// Then, in coordinates with J at 0, the line along y and F's tangent along
/// x: J = (0, 0), H1 = (0, a) with a > 0, H2 = (0, c), F = (b, c) with
/// b != 0 (F's handle cannot reach F), so x = b t^3 and
///   det(P', P'') = -18 b t (a (1 - 2t) + c t),
/// and the curvature kappa = det / |P'|^3 is 0 at t = 0. If c <= a, the
/// linear factor vanishes at some t0 in (0, 1] and kappa is 0 at both ends
/// of (0, t0) and not between: an extremum inside. If c > a, kappa keeps one
/// sign on (0, 1], and with N = t (a (1 - 2t) + c t), D = |P'|^2 (D(1) =
/// 9 b^2, D'(1) = 36 b^2), d|kappa|/dt at t = 1 has the sign of N'(1) D(1)
/// - 3/2 N(1) D'(1) = 9 b^2 (3a - 4c) < 0: |kappa| rises from 0 and falls
/// at the end, so it peaks inside. Either way the piece has a curvature
/// extremum strictly inside; its turning deviation is at least pi/4 (the
/// piece turns 90 degrees), above any constant tolerance below 0.5, so the
/// gate counts it. Checked in exact integer arithmetic (font units); the
/// join's name, or "" when there is none. Test:
/// GlyphFix.ALineJoinSquareToItsFarTangentIsRefusedWithBothGates.
std::string square_cubic_line_join(const import::Contour& c, const ReportOptions& o);

/// The same join S = (J, H1, H2, F) under the same two gates where F is
/// held (a line's end: report/contour_moves.hpp) and off the line, no
/// farther along it past J than sqrt(40)/3 (about 2.11) times its distance
/// from it: again no designer's move passes both, whatever H1 and H2 do.
/// g2 at J puts H2 on the line, and J stays smooth with H1 on it, so in
/// coordinates with J at 0 and the line along y: H1 = (0, a), a > 0,
/// H2 = (0, c), F = (b, e), b != 0, x = b t^3, and as above
///   det(P', P'') = -18 b t N(t),  N(t) = t (a (1 - 2t) + c t)
/// (e does not enter). If c <= a, N vanishes at t0 = a / (2a - c) in
/// (0, 1] and not between: kappa is 0 at 0 and t0, and has an extremum
/// strictly inside. If c > a, with r = c - a > 0 and q = e - c (F past
/// H2 along the line), kappa keeps one sign on (0, 1], |kappa| = 18 |b| N /
/// D^(3/2) with D = |P'|^2, and at t = 1 (N = r, N' = 2r - a,
/// D = 9 (b^2 + q^2), D' = 36 (b^2 + q^2 - q r)):
///   N' D - 3/2 N D' = 9 (6 r^2 q - (4r + a)(b^2 + q^2)).
/// That is negative where q <= 0. Where q > 0 (then e > c > a > 0),
/// a > 0 gives (4r + a)(b^2 + q^2) > 4r (b^2 + q^2), and r = e - q - a <
/// e - q gives 6 r^2 q < 6 r (e - q) q, so it is negative once 3 (e - q) q
/// <= 2 (b^2 + q^2), that is 5 q^2 - 3 e q + 2 b^2 >= 0, which holds for
/// every q when 9 e^2 <= 40 b^2. So |kappa| rises from 0 and falls at the
/// end: an extremum strictly inside, for every a and c. It is no
/// near-constant arc (the gate's exemption): kappa(0) = 0, so with K the
/// largest |kappa| and S <= L the arc length (L the control polygon's), F's
/// distance |b| from the start tangent's line is at most K S^2 / 2, and the
/// turning deviation (hi - lo) / 2 L >= K L / 2 >= |b| / L; with every
/// point within 2^24 units, L < 2^28, so a constant tolerance below half
/// of |b| / 2^28 cannot exempt it. No cusp: x' = 3 b t^2 != 0 on (0, 1].
/// Exact integer arithmetic (F's coordinates times |J - L|, squared in 128
/// bits); the join's name, or "" when there is none. Tests:
/// GlyphFix.ALineJoinToAHeldLineEndIsRefusedWithBothGates (and TeX Gyre
/// Heros r's stem and arch).
std::string held_cubic_line_join(const import::Contour& c, const ReportOptions& o);

/// The same join under the same two gates where F is held and off the line
/// but farther along it than that bound, so that positions off the grid may
/// pass, for a fix on the grid of integer step G where J, H1 and H2 lie on
/// it (font units: G = 1). held_cubic_line_join's derivation shows an
/// extremum strictly inside wherever c <= a, and wherever c > a with q =
/// e - c <= 0, for every e: a passing piece has 0 < a < c < e. The moves
/// keep H1 on J's line (J stays smooth) and g2 at J puts H2 there too, and
/// the grid points of that line are J + k G p, p = u / gcd(u) its primitive
/// direction (t p in G Z^2 gives t in G Z, p's coordinates being coprime).
/// So a fix on the grid has H1 = J + k1 G p, H2 = J + k2 G p with 1 <= k1 <
/// k2 and k2 G |p|^2 < E = (F - J) . p: finitely many pairs, and Algorithm
/// 1 (monotonicity alone, to o.max_depth) classifies each cubic exactly.
/// Where every one is not monotone, no move on the grid passes both gates.
/// Not near constant and no cusp, as in held_cubic_line_join (the same
/// bound on the constant tolerance). Only where there are at most
/// kMaxGridPairs pairs (else the search decides). The join's name and the
/// number of pairs checked (0 where there is no such pair); nullopt where
/// there is no such join. Test: GlyphFix.ALineJoinToAHeldLineEndWithNoPlaceOnTheGridIsRefused
/// (P052 L's serifs).
struct GridHeldJoin {
  std::string join;
  long pairs = 0;
};
inline constexpr long kMaxGridPairs = 1L << 16;
std::optional<GridHeldJoin> held_cubic_line_join_on_grid(const import::Contour& c, const ReportOptions& o,
                                                         double grid);

/// A quadratic contour's piece (N0, B, N1) from one exactly smooth node to
/// the next, its one off-curve point B the handle of both, that turns by
/// 90 degrees or more (and less than 180), under an extremum gate
/// (curvature-extrema-at-nodes, or max-extrema-per-segment:0). The
/// designer's moves keep each smooth node's tangent direction (its group
/// translates, its handles slide, never through it), so B stays where the
/// two tangents cross, a = B - N0 and b = N1 - B keep their directions, and
/// the piece keeps its turn. With c = b - a its lambda has the Bernstein
/// coefficients -48 det(a, b) (a . c) and -48 det(a, b) (b . c)
/// (quadratic_monotone); a . b <= 0 gives a . c = a . b - |a|^2 < 0 and b .
/// c = |b|^2 - a . b > 0, and det(a, b) != 0, so the curvature has an
/// extremum strictly inside, at t* = a . (a - b) / |a - b|^2. No cusp (P' =
/// 2 (a + t c) != 0 where a and b are not parallel). Not near constant:
/// with Q(t) = |a + t c|^2 and kappa = |det(a, b)| / (2 Q^(3/2)), the
/// largest |kappa| (at t*, Q* = det(a, b)^2 / |c|^2 <= |a|^2 |b|^2 / (|a|^2
/// + |b|^2), since |c|^2 = |a|^2 + |b|^2 - 2 a . b) is at least 2^(3/2)
/// times the smaller end's (Q = max(|a|^2, |b|^2)), and it times the control
/// polygon's length is at least the turn, pi / 2, so the turning deviation
/// (report.hpp) is at least (1 - 2^(-3/2)) pi / 4 > 0.5: no constant
/// tolerance below 0.5 exempts it. So no move passes the gate. Exact for
/// font units (integers within 2^24). Each such piece's (N0, B, N1) point
/// indices and its turn in degrees; the first, nullopt where there is none.
/// Test: GlyphFix.AQuadraticTurnPinnedBetweenSmoothNodesIsRefused.
struct PinnedTurn {
  int n0 = 0, b = 0, n1 = 0;
  double degrees = 0;
};
std::optional<PinnedTurn> pinned_quadratic_turn(const import::Contour& c, const ReportOptions& o);

/// Why no designer's move fixes contour `c` under `o` (the moves `movable`:
/// contour_moves, or the named points of them; `grid`, the font's), proved
/// before any search by one of the above; "" where none applies. One line
/// naming the join or piece and what a designer can do instead.
std::string refusal(const import::Contour& c, const ReportOptions& o, double grid, const std::vector<int>& movable);

}  // namespace cmr::report::glyph_detail
