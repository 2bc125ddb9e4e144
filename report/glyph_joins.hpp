#pragma once
// Internal to cmr::report: joins of a glyph's contour where no designer's
// move passes g2-at-smooth-nodes (with an extremum gate), found before the
// glyph fix searches (report/glyph_fix.cpp), so it says so at once.
#include <string>

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
/// straight chain would pass: not claimed, the search decides.) The
/// joint's name, or "" when there is none.
std::string unmovable_g2_join(const import::Contour& c, const ReportOptions& o);

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

}  // namespace cmr::report::glyph_detail
