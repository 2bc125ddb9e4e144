#include "design/kcurve.hpp"
#include "design/kcurve_detail.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "bezierize/classify.hpp"
#include "spline/errors.hpp"
#include "spline/format.hpp"

// What a solved kappa-curve becomes (kcurve.hpp): its quadratic spline, its
// certified cubic chain (CAD&A 2024 §5.2) with the chain's maxima and the
// pieces it could not certify, and the notes on points that are not maxima
// and on degenerate pieces. The solver is in kcurve.cpp.

namespace cmr {

using kcurve_detail::extent_of;
using kcurve_detail::kCoincidentRelative;

BSpline kcurve_quadratic_spline(const KCurve& curve) {
  CMR_CHECK(!curve.quadratics.empty());
  std::vector<Vec2> points{curve.quadratics.front()[0]};
  std::vector<double> knots{0, 0};
  for (std::size_t i = 0; i < curve.quadratics.size(); ++i) {
    points.push_back(curve.quadratics[i][1]);
    points.push_back(curve.quadratics[i][2]);
    knots.insert(knots.end(), 2, static_cast<double>(i + 1));
  }
  return BSpline::make(2, std::move(knots), std::move(points), curve.closed ? "kcurve-closed" : "kcurve");
}

namespace {

/// The cubic chain's pieces (each four points) and, per quadratic, the index
/// of its maximum among the chain's control points (-1 if not a handle pair).
struct Chain {
  std::vector<std::array<Vec2, 4>> pieces;
  std::vector<int> maxima;
  std::vector<int> uncertified;  ///< pieces certify_piece could not make monotone
};

/// Relative handle nudges tried by certify_piece: 2^-48 (a few hundred
/// units in the last place of the handle) up to 2^-20 (about 1e-6).
constexpr double kMinNudge = 0x1p-48;
constexpr double kMaxNudge = 0x1p-20;

std::array<Vec2, 4> elevate(Vec2 a, Vec2 m, Vec2 b) {
  return {a, (a + 2.0 * m) / 3.0, (2.0 * m + b) / 3.0, b};
}

bool finite(const std::array<Vec2, 4>& piece) {
  return std::all_of(piece.begin(), piece.end(), [](Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); });
}

/// The piece's curvature is certified monotone (or constant): Algorithm 1
/// with the exact fallback at analyze's default depth, i.e. what `cmr
/// analyze` reports for it.
bool certified_monotone(const std::array<Vec2, 4>& piece) {
  ClassifyOptions options;
  options.inflection = false;
  const Curvature c = classify_bezier(piece, options).monotonicity.curvature;
  return c == Curvature::increasing || c == Curvature::decreasing || c == Curvature::constant;
}

/// Makes a piece whose curvature extremum should lie at its end `at` (0 or
/// 3) certified monotone. In exact arithmetic the extremum is at the end;
/// rounding the split and the elevation to doubles leaves it within about
/// 1e-14 of the end, inside or outside. Inside, the handle at the other end
/// is lengthened or shortened by a relative 2^-48, 2^-46, ... (at most
/// kMaxNudge): that moves the extremum across the end while the tangent
/// directions stay those of the rounded data and the curvature at the ends
/// changes by about the same relative amount. The first nudge the exact
/// classifier certifies is kept. False when none is (the piece is left as it was).
bool certify_piece(std::array<Vec2, 4>& piece, int at) {
  if (certified_monotone(piece)) return true;
  const int end = at == 3 ? 0 : 3, handle = at == 3 ? 1 : 2;
  const std::array<Vec2, 4> original = piece;
  for (double delta = kMinNudge; delta <= kMaxNudge; delta *= 4)
    for (double sign : {1.0, -1.0}) {
      piece = original;
      piece[handle] = original[end] + (1 + sign * delta) * (original[handle] - original[end]);
      if (!finite(piece)) continue;  // near the largest double the nudge overflows: not a piece
      if (certified_monotone(piece)) return true;
    }
  piece = original;
  return false;
}

Chain cubic_chain(const KCurve& curve) {
  CMR_CHECK(curve.quadratics.size() == curve.t_max.size() && !curve.quadratics.empty());
  Chain c;
  for (std::size_t i = 0; i < curve.quadratics.size(); ++i) {
    const auto& q = curve.quadratics[i];
    const double t = curve.t_max[i];
    const Vec2 l1 = glm::mix(q[0], q[1], t), r1 = glm::mix(q[1], q[2], t), mid = glm::mix(l1, r1, t);
    const std::array<Vec2, 4> left = elevate(q[0], l1, mid), right = elevate(mid, r1, q[2]);
    // Points near the largest double: the split or the elevation overflows.
    if (!finite(left) || !finite(right))
      throw InputError("the kappa-curve's cubic pieces overflow doubles: scale the points down (to below about 1e307)");
    if (t > 0) {
      c.pieces.push_back(left);
      // The left half ends at the maximum; a whole quadratic (t = 1) has it
      // at or beyond its end.
      if (!certify_piece(c.pieces.back(), 3)) c.uncertified.push_back(static_cast<int>(c.pieces.size()) - 1);
    }
    c.maxima.push_back(t > 0 && t < 1 ? 3 * static_cast<int>(c.pieces.size()) : -1);
    if (t < 1) {
      c.pieces.push_back(right);
      if (!certify_piece(c.pieces.back(), 0)) c.uncertified.push_back(static_cast<int>(c.pieces.size()) - 1);
    }
  }
  return c;
}

}  // namespace

BSpline kcurve_cubic_chain(const KCurve& curve) {
  const Chain c = cubic_chain(curve);
  std::vector<Vec2> points{c.pieces.front()[0]};
  std::vector<double> knots{0, 0, 0};
  for (std::size_t i = 0; i < c.pieces.size(); ++i) {
    points.insert(points.end(), c.pieces[i].begin() + 1, c.pieces[i].end());
    knots.insert(knots.end(), 3, static_cast<double>(i + 1));
  }
  return BSpline::make(3, std::move(knots), std::move(points),
                       curve.closed ? "kcurve-cubic-closed" : "kcurve-cubic");
}

std::vector<int> kcurve_cubic_maxima(const KCurve& curve) { return cubic_chain(curve).maxima; }

std::vector<int> kcurve_cubic_uncertified(const KCurve& curve) { return cubic_chain(curve).uncertified; }

std::vector<std::string> kcurve_off_point_notes(const KCurve& curve, std::span<const Vec2> points) {
  std::vector<std::string> out;
  const int n = static_cast<int>(curve.quadratics.size());
  for (std::size_t k = 0; k < curve.off_point_maxima.size(); ++k) {
    const int i = curve.off_point_maxima[k];
    const int point = curve.closed ? i : i + 1;
    CMR_CHECK(point < static_cast<int>(points.size()));
    const Vec2 p = points[point];
    const auto& q = curve.quadratics[i];
    // The joint the point lies on: the start or the end of quadratic i.
    const bool at_start = glm::length(p - q[0]) <= glm::length(p - q[2]);
    const int other = at_start ? (i + n - 1) % n : (i + 1) % n;
    const int left = at_start ? other : i, right = at_start ? i : other;
    const std::string name = "points[" + std::to_string(point) + "]";
    const std::string joint = "the joint of quadratics " + std::to_string(left) + " and " + std::to_string(right);
    // Why: the point of the smooth solution farthest outside its quadratic.
    int worst = -1;
    double excess = 0;
    for (int j = 0; j < static_cast<int>(curve.unconstrained_t.size()); ++j) {
      const double u = curve.unconstrained_t[j], e = std::max(-u, u - 1);
      if (e > excess) worst = j, excess = e;
    }
    const std::string why =
        worst < 0 ? "no kappa-curve with a maximum at " + name + " was found"
                  : "the kappa-curve equations' solution near this answer needs points[" +
                        std::to_string(curve.closed ? worst : worst + 1) + "] at t = " +
                        format_number(curve.unconstrained_t[worst], 3) + " of quadratic " + std::to_string(worst) +
                        ", outside it";
    if (std::count(curve.stray_maxima.begin(), curve.stray_maxima.end(), i) > 0) {
      // How far the peak is from the point, for the designer's eye.
      const double t = curve.t_max[i], v = 1 - t;
      const Vec2 peak = v * v * q[0] + 2 * t * v * q[1] + t * t * q[2];
      const double share = glm::length(peak - p) / extent_of(points);
      out.push_back("quadratic " + std::to_string(i) + " peaks at t = " + format_number(t, 3) +
                    ", at none of the points, and " + name + " lies on " + joint + ", " +
                    format_number(100 * share, 3) + "% of the points' extent from that peak (" + why +
                    "; docs/kcurve.md)");
      continue;
    }
    // |κ| falls into the joint along the left quadratic and rises out of it
    // along the right one: a minimum.
    const bool minimum = curve.t_max[left] < 1 && curve.t_max[right] > 0;
    out.push_back(name + " is not a curvature maximum: it lies on " + joint +
                  (minimum ? ", where |kappa| has a minimum" : "") +
                  "; every maximum of |kappa| is at a point (" + why + "; docs/kcurve.md)");
  }
  return out;
}

std::vector<int> kcurve_degenerate_pieces(const KCurve& curve) {
  // Coordinate differences only (no squares): far-scale curves (1e154)
  // neither overflow nor underflow here.
  double lo_x = std::numeric_limits<double>::infinity(), hi_x = -lo_x, lo_y = lo_x, hi_y = -lo_x;
  for (const auto& q : curve.quadratics)
    for (const Vec2& c : q) {
      lo_x = std::min(lo_x, c.x), hi_x = std::max(hi_x, c.x);
      lo_y = std::min(lo_y, c.y), hi_y = std::max(hi_y, c.y);
    }
  const double extent = std::max(hi_x - lo_x, hi_y - lo_y);
  std::vector<int> out;
  for (std::size_t i = 0; i < curve.quadratics.size(); ++i) {
    const auto& q = curve.quadratics[i];
    const double chord = std::max(std::abs(q[2].x - q[0].x), std::abs(q[2].y - q[0].y));
    if (!(chord > kCoincidentRelative * extent)) out.push_back(static_cast<int>(i));
  }
  return out;
}

}  // namespace cmr
