#pragma once
/// The interpolation gates (issue 37; `cmr report FAMILY.designspace
/// --require g1-between-masters`, or a variable font): judged on every
/// piece of the design space where points move affinely
/// (io/masters.hpp), not only at the masters.
///
/// g1-between-masters. Every node that is smooth at the masters stays G1 at
/// every location of each piece. Along a piece (parameter s in [0, 1]) every
/// control point is P(s) = (1 - s) A + s B, and so is every Bezier point of
/// every segment (an affine function of the control points; exact for
/// A and B the piece's end splines, built exactly from the masters as
/// (1 - s0) M_a + s0 M_b, io/masters.hpp's Piece::s0, s1). At the node that
/// ends segment i-1 (Bezier points L_0..L_n) and starts segment i (R_0..R_n)
/// the tangents are
///
///   u(s) = L_n - L_{n-1},  v(s) = R_1 - R_0     (each affine: degree 1 in s)
///
/// (a handle of zero length at both ends of the piece: the next point,
/// L_n - L_{n-2} or R_2 - R_0). The node is G1 at s exactly when
///
///   c(s) = u(s) x v(s) = 0   and   d(s) = u(s) . v(s) > 0,
///
/// c and d polynomials of degree <= 2 in s, in Bernstein form on [0, 1]:
///   c = [u0 x v0, (u0 x v1 + u1 x v0) / 2, u1 x v1]    (d likewise with .)
/// with exact rational coefficients (the inputs are doubles: every double is
/// a rational, numeric/exact.hpp).
///
/// "Smooth at the masters" (the nodes judged): the node is marked smooth
/// (a .glif's smooth="yes") in both masters of the piece, AND c = 0 and
/// d > 0 exactly at both ends of the piece (s = 0 and s = 1). A node the
/// designer marked smooth whose tangents are off by float noise at a master
/// (non-integer coordinates, e.g. 455.53248462973204 after an off-grid fix)
/// is *not* collinear at that master in exact arithmetic; it is not judged
/// here (g2-at-smooth-nodes and the G1 tolerance of cmr analyze judge the
/// masters themselves). Integer masters, as UFO sources usually are, make
/// the test exact with no tolerance at all. A binary variable font has no
/// smooth marks: collinearity at both ends decides alone.
///
/// The certificate: c == 0 (its three coefficients are zero) and d > 0 on
/// [0, 1] (no root of d there: isolate_roots): the node is G1 at every
/// location of the piece. Otherwise a violation: the open s-intervals
/// between consecutive roots of c in [0, 1] (c(0) = c(1) = 0 and c of
/// degree <= 2 not identically zero leave exactly (0, 1): the node is a kink
/// at every location strictly between), or, c == 0, where d <= 0 (the
/// tangents reverse or a handle collapses). The worst instance: the angle
/// between u and v is theta(s) = atan2(c(s), d(s)) with
///
///   theta'(s) = (c' d - c d') / (c^2 + d^2),
///
/// and g = c' d - c d' has degree <= 2 (its s^3 terms cancel), so |theta|
/// is largest at a root of g in (0, 1) (isolated exactly; theta = 0 at the
/// ends): the worst angle, in degrees, is evaluated there (double precision
/// at the enclosure's middle, within 1e-12 in s), and its location is given
/// in the user's axis values ("Weight": 437.5).
///
/// g1-between-masters:DEG (DEG in (0, 90) degrees), for masters rounded to
/// a grid, whose smooth nodes are rarely exactly collinear: a node marked
/// smooth at both masters whose tangents turn by at most DEG at both ends
/// must turn by at most DEG at every location between. With T = tan(DEG)
/// (the double's exact rational value),
///
///   |theta(s)| <= DEG  <=>  d(s) > 0,  h+(s) = T d - c >= 0,  h-(s) = T d + c >= 0,
///
/// h+ and h- of degree <= 2 (Bernstein coefficients T d_k -+ c_k): the node
/// is judged when this holds at both masters, and fails on the open
/// s-intervals where h+ < 0, h- < 0 or d < 0 (between their exact roots);
/// the worst angle as above. DEG = 0 is the exact rule (h+ = -c and
/// h- = c both >= 0 on [0, 1] is c == 0), kept on its own path.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "numeric/exact.hpp"
#include "io/masters.hpp"
#include "report/font_report.hpp"
#include "report/gates.hpp"
#include "report/merge.hpp"

namespace cmr::report {

/// A node's tangents along a piece: u(s) = (1 - s) u0 + s u1, v likewise
/// (exact).
struct NodeTangents {
  Rational u0x, u0y, u1x, u1y, v0x, v0y, v1x, v1y;
};

/// G1 at one instance: u x v = 0 and u . v > 0, exactly; with tan_turn =
/// T > 0, within the turn: u . v > 0 and |u x v| <= T u . v.
bool g1_at(const Rational& ux, const Rational& uy, const Rational& vx, const Rational& vy,
           const Rational& tan_turn = Rational(0));

/// What g1-between-masters finds at one node on one piece (the caller
/// judges only nodes smooth at the masters: g1_at at both).
struct G1Between {
  bool judged = false;    ///< set by g1_between
  bool holds = false;     ///< certified G1 at every s in [0, 1]
  /// Where it fails: open intervals of s (c != 0, or d <= 0 with c == 0);
  /// ends rounded outwards to doubles (exact when they are dyadic).
  std::vector<std::pair<double, double>> fail;
  double worst_s = 0;      ///< the worst instance (nearest double)
  double worst_angle = 0;  ///< degrees, at worst_s
};

/// The test of the header comment on one node's tangents over s in [0, 1]
/// (a piece's own parameter: for a --between part of the masters' line the
/// ends need not be G1, and the worst angle may lie at an end).
/// tan_turn > 0: the turn of g1-between-masters:DEG, T = tan(DEG); `fail`
/// then gives where the turn exceeds DEG.
G1Between g1_between(const NodeTangents& t, const Rational& tan_turn = Rational(0));

/// One family of fixes at one node, in one master, on the integer grid: the
/// moves that keep the master's own tangent (g1-between-masters:DEG tries
/// it first; the exact gate's least move over every grid position is
/// g1_least_move below). At master m the node N has its incoming handle
/// H_in and outgoing H_out, exactly collinear with N and on the integer
/// grid: u = N - H_in = alpha g, v = H_out - N = beta g with g the primitive
/// integer direction (gcd of its coordinates 1) and alpha, beta positive
/// integers; at the other master u' = alpha' g', v' = beta' g'. Then
///
///   c(s) = 2 s (1 - s) c1,  2 c1 = u x v' + u' x v = (alpha beta' - alpha' beta) (g x g'),
///
/// so the node is G1 at every location iff g x g' = 0 or alpha / beta =
/// alpha' / beta' = p / q (reduced). The handles of master m that keep g and
/// the grid and make it G1 are alpha = p k, beta = q k (k >= 1, integer): the
/// total move |p k - alpha| |g| + |q k - beta| |g| is convex and piecewise
/// linear in k, least at k = floor or ceil of alpha / p or beta / q. With
/// c == 0, u(s) = (p / q) v(s), so d > 0 unless v(s) = 0 somewhere (g' = -g
/// direction: the node reverses, which no such move fixes). Refused
/// (nullopt): coordinates not integers, a handle of zero length, a node not
/// exactly G1 at a master, or g' opposite to g.
struct G1NodeFix {
  Vec2 in_handle{}, out_handle{};  ///< the master's new handles
  double distance = 0;             ///< |H_in' - H_in| + |H_out' - H_out|
};
/// node, in_handle, out_handle: at the master whose handles move ([0]) and
/// at the other ([1]). A node already G1 between them: its handles
/// unmoved, distance 0. `in_fixed` / `out_fixed`: that side is a line (its
/// "handle" is the line's other end, a node that stays), so its length is
/// kept: k = alpha / p (beta / q) when that is an integer, else nullopt;
/// only the other handle moves. Both fixed: only an already proportional
/// node passes.
std::optional<G1NodeFix> g1_between_fix(const Vec2 node[2], const Vec2 in_handle[2], const Vec2 out_handle[2],
                                        bool in_fixed = false, bool out_fixed = false);

/// The least move for the exact gate (issue 37 item 4: "the smallest total
/// move"), over every position on the integer grid of one master m's
/// handles, the nodes fixed. At m a node has u = N - H_in, v = H_out - N;
/// at a neighbour o of a piece on which the node is judged, u' and v' = r u'
/// (collinear: r = beta' / alpha' > 0, rational). With u' x v' = 0 the
/// cross product c(s) = (1 - s)^2 (u x v) + s (1 - s) (u x v' + u' x v) +
/// s^2 (u' x v') vanishes identically iff u x v = 0 (G1 at m: v = lambda u,
/// lambda > 0) and
///
///   u x v' + u' x v = r (u x u') + lambda (u' x u) = (r - lambda) (u x u') = 0,
///
/// that is, lambda = r (m takes o's handle ratio, in any direction) or
/// u x u' = 0 (m's tangent along o's, any ratio; u . u' < 0 would reverse
/// the tangent between: refused). Then d(s) = u(s) . v(s) > 0 on [0, 1]:
/// with lambda = r, v(s) = r u(s) and u(s) != 0; along u', both are
/// positive multiples of one direction. So, given u, the outgoing vector is
/// fixed (v = r u, on the grid when r u is) or free along u's primitive
/// integer direction w (v = j w, j >= 1: the nearest j to the old v is a
/// floor or ceiling of its projection), and the least total move is
///
///   min over grid u of |u - u_old| + min over those v of |v - v_old|,
///
/// searched in square rings around u_old, stopping at the first ring whose
/// distance reaches the best total (every further u costs more): the answer
/// is the least over every grid position, not a family of them. A side
/// that is a line stays (its vector is given); with the incoming side a
/// line the outgoing vector follows directly (u = v / r symmetrically).
/// Nodes sharing handles (a quadratic source's off-curve point between two
/// on-curve points), a run of them or a closed ring, are searched together:
/// the run's first handle in rings; along the run each next handle follows
/// (a point, or every grid point of a ray the remaining budget reaches:
/// branch and bound, exhaustive since every move is >= 0); the last
/// node's outgoing handle is the nearest it may be, and on a ring it must be
/// the first handle. `keep_g1`: a node not judged on any piece with m but
/// G1 at m (and marked smooth) stays G1 there.
struct G1NodeRule {
  Vec2 node{}, in_handle{}, out_handle{};         ///< at master m (integers)
  bool in_fixed = false, out_fixed = false;       ///< that side is a line: its end stays
  std::vector<std::array<Vec2, 2>> others;        ///< (u', v') at each neighbour of a judged piece (any doubles)
  bool keep_g1 = true;                            ///< stays G1 at m (v a positive multiple of u)
};
struct G1LeastMove {
  std::vector<G1NodeFix> nodes;  ///< per rule: its new handles and their move
  double distance = 0;           ///< the total (a shared point counted once)
};
/// rules: a run of nodes, each one's outgoing handle the same point as the
/// next one's incoming (and, `closed`, the last one's the first one's);
/// in a run of two or more every node has a rule (neighbours or keep_g1).
/// nullopt: m's coordinates not integers (or beyond 1e9), a neighbour's not
/// multiples of 2^-30 (they need not be integers), a zero tangent, or no
/// grid move within `reach` units.
std::optional<G1LeastMove> g1_least_move(const std::vector<G1NodeRule>& rules, bool closed = false,
                                         double reach = 1024);

/// `cmr fix FAMILY.designspace --glyph NAME --require g1-between-masters`
/// (two masters or more in their UFOs' default layers, cubic outlines): on
/// every piece between adjacent masters (io/masters.hpp), every node of the
/// glyph marked smooth and exactly G1 at both of its masters is judged
/// (g1_between). The handles move in one master m, the same for all kinks:
/// each kinked node must have its kinks on pieces with m only. Exact gate:
/// each kinked node (with a node sharing its handle) takes g1_least_move
/// against all of m's neighbours, the least move over every grid position
/// of its handles (`least` = true). g1-between-masters:DEG: the cheapest of
/// three families of moves (g1_between_fix, ratio_turn_fixes,
/// parallel_turn_fix) that holds on every piece with m (`least` = false).
/// Of the masters so fixable, the one with the smallest total move; it is
/// re-judged exactly on every piece with every edit applied (kinks_before
/// and kinks_after count node-piece pairs).
/// InputError (one line): fewer than two masters, the glyph missing or
/// incompatible, a kink no grid move in one master fixes (named).
struct MastersG1Fix {
  std::string master;  ///< the source whose handles move (its name)
  std::string ufo;     ///< its UFO folder
  std::string glif;    ///< its .glif
  std::vector<import::PointEdit> edits;  ///< the moved points (contour index, source point, x, y)
  struct Move {
    std::string point;  ///< "O/c0/p1"
    Vec2 from{}, to{};
    double distance = 0;
  };
  std::vector<Move> moves;
  int kinks_before = 0, kinks_after = 0;
  double distance = 0;  ///< total move
  bool least = false;   ///< proven the least total move in one master (the exact gate)
};
MastersG1Fix fix_g1_between_masters(const std::string& designspace, const std::string& glyph, double turn_degrees = 0);

/// g1-between-masters:DEG's other family of moves (fix_g1_between_masters
/// with turn_degrees > 0): each of master [0]'s handles moved onto the ray
/// of master [1]'s tangent from the node, H_in = N - a w_u, H_out = N + b w_v
/// (w: the tangent's primitive integer direction, so the points stay on the
/// grid; a, b >= 1 the grid points nearest the handles). Then u(s) =
/// ((1 - s) a' + s) u1 and v(s) = ((1 - s) b' + s) v1 with positive factors
/// at every location s, so the node's turn is master [1]'s throughout:
/// within DEG when it is so there. nullopt: coordinates not integers, a zero
/// tangent.
std::optional<G1NodeFix> parallel_turn_fix(const Vec2 node[2], const Vec2 in_handle[2], const Vec2 out_handle[2]);

/// The violations of g1-between-masters on one contour's report (its
/// motions: SplineReport::motions); none without motions. turn_degrees:
/// g1-between-masters:DEG (0: exactly G1).
std::vector<GateViolation> g1_between_violations(const SplineReport& report, double turn_degrees = 0);

/// curvature-between-masters (extrema = false) and extrema-between-masters
/// (true) on one contour's report: per segment and piece, when the segment's
/// curvature is monotone at both masters of the piece (Algorithm 1 on each
/// master: monotone_between of a master with itself), monotone_between of
/// the two (bezierize/between.hpp): `fails` gives the first failing location
/// (an exact dyadic s, the instance's extremum at t_witness; the infimum of
/// the failing s lies in [s_lower, s_first_fail]); `undecided` is a
/// violation too, naming the part certified. A piece that is part s0..s1 of
/// its masters' line is judged on the whole line (exact doubles) and holds
/// when the line is certified up to s1. extrema: the same, and a node that
/// is a curvature extremum at both masters (lambda's signs at it differ on
/// its two sides) must keep both signs for every s (node_lambda_between).
std::vector<GateViolation> curvature_between_violations(const SplineReport& report, bool extrema);

/// The report items of a designspace or variable font judged by the
/// interpolation gates: the default master's contours (font_inputs), each
/// carrying its motions along the pieces (io/masters.hpp read_masters).
/// `shard`: only the glyphs of that part (`--shard i/N`, the file at
/// `position`: keep_shard_glyphs), as a font's report keeps them.
FontInfo interpolation_inputs(const std::string& path, const import::GlyphSelection& which,
                              const std::optional<import::Segment2>& between, std::vector<ReportInput>& inputs,
                              const std::optional<Shard>& shard = std::nullopt, std::size_t position = 0);

}  // namespace cmr::report
