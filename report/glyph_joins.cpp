#include "report/glyph_joins.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "bezierize/extract.hpp"
#include "design/fix.hpp"
#include "report/batch.hpp"
#include "report/contour_moves.hpp"
#include "report/glyph_settle.hpp"
#include "spline/fields.hpp"
#include "spline/format.hpp"

namespace cmr::report::glyph_detail {

namespace {

/// Every line-to-quadratic smooth join of `c` where g2-at-smooth-nodes (a
/// tolerance below 1) fails (glyph_joins.hpp), each with the chain of pieces
/// that would have to be straight: from J along the curved side while g2
/// applies at the next joint and no line starts there.
struct StraightChain {
  int joint = 0;            ///< J: the joint's index
  Vec2 j{0.0}, u{0.0};      ///< J's position and its line's direction
  std::vector<int> pieces;  ///< the chain, from J
  int far_joint = -1;       ///< where it ends: a corner's or a line's joint (-1: it closes on itself)
  bool held_off = false;    ///< it ends at a line's end (which stays) off J's line
};
std::vector<StraightChain> straight_chains(const import::Contour& c, const ReportOptions& o) {
  const BSpline& s = c.spline;
  std::vector<StraightChain> out;
  if (s.degree() != 2 || !s.closed()) return out;
  if (std::none_of(o.gates.begin(), o.gates.end(),
                   [](const Gate& g) { return g.kind == Gate::Kind::g2_at_smooth_nodes && g.tolerance < 1; }))
    return out;
  const SplineReport r = gate_report(s, o);
  const int n = s.segment_count();
  auto is_line = [&](int i) {
    for (int k : segment_points(s, s.segments()[i]))
      if (k < static_cast<int>(c.font_point.size()) && c.font_point[k] < 0) return true;
    return false;
  };
  std::vector<const JointReport*> joint(static_cast<std::size_t>(n), nullptr);
  for (const JointReport& jr : r.joints) joint[static_cast<std::size_t>(jr.joint.index % n)] = &jr;
  auto points = [&](int i) { return bezier_segment(s, s.segments()[static_cast<std::size_t>(i)]).points; };
  for (const JointReport& jr : r.joints) {
    const double kl = jr.joint.kappa_left, kr = jr.joint.kappa_right;
    if (jr.corner || !std::isfinite(kl) || !std::isfinite(kr) || (kl == 0) == (kr == 0)) continue;
    const int right = jr.joint.index % n, left = (right + n - 1) % n;
    const bool line_left = kl == 0;
    if (!is_line(line_left ? left : right)) continue;
    const std::vector<Vec2> line = points(line_left ? left : right);
    StraightChain chain;
    chain.joint = right;
    chain.j = line_left ? line.back() : line.front(), chain.u = line.back() - line.front();
    // From J along the curved side (forward: J starts the piece after the line), piece by piece.
    const bool forward = line_left;
    int piece = forward ? right : left;
    for (int step = 0; step < n; ++step) {
      chain.pieces.push_back(piece);
      const std::vector<Vec2> b = points(piece);
      const Vec2 end = forward ? b.back() : b.front();
      const int far = forward ? (piece + 1) % n : piece, next = forward ? (piece + 1) % n : (piece + n - 1) % n;
      if (is_line(next)) {
        chain.far_joint = far, chain.held_off = det(end - chain.j, chain.u) != 0;
        break;
      }
      if (joint[static_cast<std::size_t>(far)] == nullptr || joint[static_cast<std::size_t>(far)]->corner) {
        chain.far_joint = far;
        break;
      }
      piece = next;
    }
    out.push_back(std::move(chain));
  }
  return out;
}

std::string point_name(const import::Contour& c, int k) {
  return k < static_cast<int>(c.point_names.size()) ? c.point_names[k] : std::string("P").append(std::to_string(k));
}

std::string joint_name(const import::Contour& c, int joint) {
  return joint < static_cast<int>(c.joint_names.size()) ? c.joint_names[joint] : "joint " + std::to_string(joint);
}

}  // namespace

std::string unmovable_g2_join(const import::Contour& c, const ReportOptions& o) {
  for (const StraightChain& chain : straight_chains(c, o))
    if (chain.held_off) return joint_name(c, chain.joint);
  return "";
}

std::optional<FlatteningJoin> flattening_g2_join(const import::Contour& c, const ReportOptions& o) {
  const BSpline& s = c.spline;
  std::optional<FlatteningJoin> best;
  for (const StraightChain& chain : straight_chains(c, o)) {
    if (chain.held_off) continue;
    FlatteningJoin out;
    out.join = joint_name(c, chain.joint);
    out.far = chain.far_joint >= 0 ? joint_name(c, chain.far_joint) : "";
    // Every control point the chain's pieces hold, at its distance from J's line.
    const double length = std::sqrt(dot(chain.u, chain.u));
    for (int piece : chain.pieces)
      for (int k : segment_points(s, s.segments()[static_cast<std::size_t>(piece)])) {
        const int point = k % s.unique_point_count();
        const double d = std::abs(det(s.points()[point] - chain.j, chain.u)) / length;
        if (d > out.distance) out.distance = d, out.point = point_name(c, point);
      }
    if (out.distance > 0 && (!best || out.distance > best->distance)) best = std::move(out);
  }
  return best;
}

namespace {

__extension__ using Wide = __int128;  // GCC's, named once (-Wpedantic)

/// A cubic contour's smooth join of a line and a curve piece S = (J, H1, H2,
/// F): J a source node exactly smooth with the line (the line's added inner
/// point next to J, its other node L), H1 and H2 S's source handles; L, J,
/// H1, H2 and F integers within 2^24 (font units: the products below are
/// exact). u = J - L, the line's direction into J; `after`, the point after F.
struct CubicLineJoin {
  int j = 0, h1 = 0, h2 = 0, f = 0, after = 0;
  Vec2 u{0.0};
};

/// Font units: an integer within 2^24.
bool grid(Vec2 p) {
  return p.x == std::floor(p.x) && p.y == std::floor(p.y) && std::abs(p.x) <= 0x1p24 && std::abs(p.y) <= 0x1p24;
}

/// Every such join of `c` (a closed polynomial cubic contour; none else).
std::vector<CubicLineJoin> cubic_line_joins(const import::Contour& c) {
  const BSpline& s = c.spline;
  std::vector<CubicLineJoin> out;
  if (s.degree() != 3 || s.is_rational() || !s.closed()) return out;
  const std::vector<Vec2>& P = s.points();
  const int m = static_cast<int>(c.node.size());
  if (m < 6 || static_cast<int>(c.font_point.size()) != m) return out;
  const auto at = [&](int k) { return ((k % m) + m) % m; };
  const auto real_handle = [&](int k) { return !c.node[at(k)] && c.font_point[at(k)] >= 0; };
  for (int j = 0; j < m; ++j) {
    if (!c.node[j] || c.font_point[j] < 0) continue;
    for (const int dir : {1, -1}) {
      // S on side dir: J, H1, H2, F; the line on the other side (its added
      // inner point next to J), ending at the node L.
      const int h1 = at(j + dir), h2 = at(j + 2 * dir), f = at(j + 3 * dir), before = at(j - dir);
      if (!real_handle(h1) || !real_handle(h2) || !c.node[f] || c.node[before] || c.font_point[before] >= 0) continue;
      int l = before;
      while (!c.node[l] && l != j) l = at(l - dir);
      if (l == j) continue;
      const int after = at(f + dir);
      if (!grid(P[j]) || !grid(P[l]) || !grid(P[h1]) || !grid(P[h2]) || !grid(P[f])) continue;
      const Vec2 u = P[j] - P[l], e = P[h1] - P[j];  // the line's direction into J, J's handle
      if (det(u, e) != 0 || !(dot(u, e) > 0)) continue;  // J exactly smooth
      out.push_back({j, h1, h2, f, after, u});
    }
  }
  return out;
}

/// An extremum gate: curvature-extrema-at-nodes, or max-extrema-per-segment:0.
bool extremum_gate(const ReportOptions& o) {
  return std::any_of(o.gates.begin(), o.gates.end(), [](const Gate& g) {
    return g.kind == Gate::Kind::extrema_at_nodes ||
           (g.kind == Gate::Kind::max_extrema_per_segment && g.max_extrema == 0);
  });
}

/// Both gates the cubic proofs below need: g2-at-smooth-nodes (tolerance
/// below 1) and an extremum gate.
bool g2_and_extrema(const ReportOptions& o) {
  return extremum_gate(o) && std::any_of(o.gates.begin(), o.gates.end(), [](const Gate& g) {
           return g.kind == Gate::Kind::g2_at_smooth_nodes && g.tolerance < 1;
         });
}

}  // namespace

std::string square_cubic_line_join(const import::Contour& c, const ReportOptions& o) {
  if (!(o.constant_tolerance < 0.5) || !g2_and_extrema(o)) return "";
  const std::vector<Vec2>& P = c.spline.points();
  for (const CubicLineJoin& x : cubic_line_joins(c)) {
    // F exactly smooth: its tangent d, and the point after it (a handle) on the same line, in the same direction.
    if (!grid(P[x.after])) continue;
    const Vec2 d = P[x.f] - P[x.h2], after = P[x.after] - P[x.f];
    if (d == Vec2(0.0) || det(d, after) != 0 || !(dot(d, after) > 0)) continue;
    if (dot(P[x.h1] - P[x.j], d) != 0) continue;  // F's tangent square to the line
    return point_name(c, x.j);
  }
  return "";
}

std::string held_cubic_line_join(const import::Contour& c, const ReportOptions& o) {
  if (!g2_and_extrema(o)) return "";
  const std::vector<Vec2>& P = c.spline.points();
  const ContourMoves moves = contour_moves(c);
  for (const CubicLineJoin& x : cubic_line_joins(c)) {
    if (moves.movable(x.f)) continue;  // F held: a line's end
    // F's offset from the line and its reach along it past J, both times |u|
    // (exact: integers below 2^52); their squares in 128 bits.
    const Vec2 fj = P[x.f] - P[x.j];
    const auto B = static_cast<long long>(det(x.u, fj)), E = static_cast<long long>(dot(x.u, fj));
    if (B == 0) continue;
    if (E > 0 && 9 * static_cast<Wide>(E) * E > 40 * static_cast<Wide>(B) * B) continue;
    // Not near constant: its turning deviation is at least |b| / L (header), L below 2^28 in the box of 2^24.
    const double b = std::abs(static_cast<double>(B)) / std::sqrt(dot(x.u, x.u));
    if (!(o.constant_tolerance < 0.5 * b / 0x1p28)) continue;
    return point_name(c, x.j);
  }
  return "";
}

std::optional<GridHeldJoin> held_cubic_line_join_on_grid(const import::Contour& c, const ReportOptions& o,
                                                         double grid) {
  if (!g2_and_extrema(o) || !(grid >= 1) || grid != std::floor(grid) || grid > 0x1p24) return {};
  const auto G = static_cast<long long>(grid);
  const auto on_grid = [&](Vec2 q) { return std::fmod(q.x, grid) == 0 && std::fmod(q.y, grid) == 0; };
  const std::vector<Vec2>& P = c.spline.points();
  const ContourMoves moves = contour_moves(c);
  ClassifyOptions classify;
  classify.max_depth = o.max_depth;
  classify.inflection = false;
  for (const CubicLineJoin& x : cubic_line_joins(c)) {
    if (moves.movable(x.f) || !on_grid(P[x.j]) || !on_grid(P[x.h1]) || !on_grid(P[x.h2])) continue;
    // p, the line's primitive direction; F's offset B from the line and its reach E along it past J, both
    // times |p| (integers below 2^26: exact).
    const auto ux = static_cast<long long>(x.u.x), uy = static_cast<long long>(x.u.y);
    const long long g = std::gcd(ux, uy), px = ux / g, py = uy / g;
    const Vec2 p(static_cast<double>(px), static_cast<double>(py)), fj = P[x.f] - P[x.j];
    const auto B = static_cast<long long>(det(p, fj)), E = static_cast<long long>(dot(p, fj));
    if (B == 0) continue;
    const double b = std::abs(static_cast<double>(B)) / std::sqrt(dot(p, p));
    if (!(o.constant_tolerance < 0.5 * b / 0x1p28)) continue;
    // The steps k with k G |p|^2 < E, and their ordered pairs.
    const long long step = G * (px * px + py * py), k_max = E > 0 ? (E - 1) / step : 0;
    const long pairs = static_cast<long>(k_max * (k_max - 1) / 2);
    if (pairs > kMaxGridPairs) continue;
    const auto at = [&](long long k) { return P[x.j] + static_cast<double>(k * G) * p; };
    bool passes = false;
    for (long long k1 = 1; k1 < k_max && !passes; ++k1)
      for (long long k2 = k1 + 1; k2 <= k_max && !passes; ++k2) {
        const std::array<Vec2, 4> piece = {P[x.j], at(k1), at(k2), P[x.f]};
        passes = classify_bezier(piece, classify).monotonicity.curvature != Curvature::non_monotone;
      }
    if (!passes) return GridHeldJoin{point_name(c, x.j), pairs};
  }
  return {};
}

std::optional<PinnedTurn> pinned_quadratic_turn(const import::Contour& c, const ReportOptions& o) {
  const BSpline& s = c.spline;
  if (!extremum_gate(o) || !(o.constant_tolerance < 0.5) || s.degree() != 2 || s.is_rational() || !s.closed())
    return {};
  const int m = static_cast<int>(c.node.size());
  if (m < 3 || s.unique_point_count() != m || static_cast<int>(c.font_point.size()) != m) return {};
  const std::vector<Vec2> P(s.points().begin(), s.points().begin() + m);
  for (int b = 0; b < m; ++b) {
    const int n0 = (b + m - 1) % m, n1 = (b + 1) % m;
    if (c.node[b] || c.font_point[b] < 0 || !c.node[n0] || !c.node[n1] || c.font_point[n0] < 0 ||
        c.font_point[n1] < 0)
      continue;
    if (!grid(P[n0]) || !grid(P[b]) || !grid(P[n1]) || !exactly_smooth(P, m, n0) || !exactly_smooth(P, m, n1))
      continue;
    const Vec2 u = P[b] - P[n0], v = P[n1] - P[b];
    if (det(u, v) == 0 || dot(u, v) > 0) continue;
    const double cosine = dot(u, v) / std::sqrt(dot(u, u) * dot(v, v));
    return PinnedTurn{n0, b, n1, std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / std::numbers::pi};
  }
  return {};
}

std::string refusal(const import::Contour& c, const ReportOptions& o, double grid, const std::vector<int>& movable) {
  // "g2-at-smooth-nodes at JOIN" and why (appended: GCC 12 warns (-Wrestrict) on "..." + string).
  const auto at_join = [](const std::string& join) { return std::string("g2-at-smooth-nodes at ").append(join); };
  if (movable.empty()) return "no source point may move (every node ends a straight piece)";
  if (const std::string join = unmovable_g2_join(c, o); !join.empty()) {
    return at_join(join).append(
        " joins a line to a quadratic curve smoothly: the curve's end curvature would have to be 0, which a quadratic "
        "piece has only when straight, so no move of the points passes, nor would an added on-curve point (the jump "
        "moves to wherever the straight part meets the curved one); accept the jump, or draw the curve in cubics");
  }
  // Where every fix flattens a curve by more than a few grid steps it is a curve, not a near-line that a
  // fix may straighten: refused with what every fix would do. (Within a few steps the search runs: it can
  // straighten a curve meant to be straight.)
  constexpr double kFlatteningSteps = 4;
  if (const std::optional<FlatteningJoin> flat = flattening_g2_join(c, o);
      flat && flat->distance > kFlatteningSteps * (grid > 0 ? grid : 1)) {
    return at_join(flat->join)
               .append(" joins a line to a quadratic curve smoothly: the curve's end curvature would have to "
                       "be 0, which a quadratic piece has only when straight, and then so would each next piece "
                       "along the curve, ")
               .append(flat->far.empty() ? std::string("all round the contour") : "up to " + flat->far)
               .append(": every fix lays that curve on the line, moving ")
               .append(flat->point)
               .append(" at least ")
               .append(format_number(flat->distance, 4))
               .append(" units, which flattens the shape rather than fixing it (accept the jump, or draw the "
                       "curve in cubics)");
  }
  if (const std::string join = square_cubic_line_join(c, o); !join.empty()) {
    return at_join(join).append(
        " joins a line to a cubic whose far node's tangent is square to the line: g2 there puts the cubic's second "
        "handle where the two lines cross, and then its curvature has an extremum inside the piece, so no move that "
        "keeps lines straight and smooth nodes smooth passes both gates (add an on-curve point: " + field("add_nodes") +
        " tries that; or accept the jump)");
  }
  if (const std::string join = held_cubic_line_join(c, o); !join.empty()) {
    return at_join(join).append(
        " joins a line to a cubic that ends at a line's end, which stays, no farther along the line than about 2.1 "
        "times its distance from it: g2 there puts both handles on the line, and then the cubic's curvature has an "
        "extremum inside the piece wherever they are, so no move that keeps lines straight and smooth nodes smooth "
        "passes both gates (add an on-curve point: " + field("add_nodes") + " tries that; or accept the jump)");
  }
  if (const std::optional<GridHeldJoin> on_grid = held_cubic_line_join_on_grid(c, o, grid)) {
    return at_join(on_grid->join)
        .append(" joins a line to a cubic that ends at a line's end, which stays: g2 there puts both handles on the "
                "line, in order short of the end's foot on it if the curvature is to be monotone, and exact analysis "
                "finds an extremum inside the cubic for each of the ")
        .append(std::to_string(on_grid->pairs))
        .append(" such pairs of grid positions, so no move on the grid that keeps lines straight and smooth nodes "
                "smooth passes both gates (add an on-curve point: ")
        .append(field("add_nodes"))
        .append(" tries that; or accept the jump)");
  }
  if (const std::optional<PinnedTurn> turn = pinned_quadratic_turn(c, o)) {
    return std::string("the extremum gate: the quadratic piece ")
               .append(point_name(c, turn->n0))
               .append(", ")
               .append(point_name(c, turn->b))
               .append(", ")
               .append(point_name(c, turn->n1))
               .append(" turns by ")
               .append(format_number(turn->degrees, 3))
               .append(" degrees between two smooth nodes, whose tangents every move keeps, so its off-curve "
                       "point stays where they cross and the piece keeps its turn; a quadratic piece that turns "
                       "by 90 degrees or more has a curvature extremum inside, so no move of the points passes "
                       "(add an on-curve point, or accept the extremum)");
  }
  return "";
}

}  // namespace cmr::report::glyph_detail
