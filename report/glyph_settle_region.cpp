// The settling's proofs of failure (glyph_settle.hpp): extremum_rejects (a
// unit's candidate positions that its region proves fail the
// curvature-extrema gate) and with_failure_proofs (a candidate's curvature
// extremum or curvature jump shown before the judge runs). Either passes a
// position over only where the judge would fail it.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

#include "bezierize/analyze.hpp"
#include "bezierize/classify.hpp"
#include "bezierize/extract.hpp"
#include "design/fix.hpp"
#include "region/region.hpp"
#include "report/glyph_settle.hpp"

namespace cmr::report::glyph_detail {
namespace {

/// The proofs' relative margin: far above the rounding of the doubles they
/// read (Bezier points rounded from the control points; certified
/// curvatures, within kKappaRelError = 1e-11 of the exact ones).
constexpr double kMargin = 1e-9;

/// Whether a segment's Bezier points `b` (degree n >= 2) certainly leave
/// both of the gate's exemptions out, so that a curvature extremum inside
/// it (lambda changing sign, which the region's "fail" says) is a violation:
///  * no cusp: P'(t) = n sum B_i(t) h_i (h_i = b_{i+1} - b_i) never vanishes
///    where some direction u has u.h_i > 0 for every i (tried: h_0, h_{n-1}
///    and their sum), with a margin far above the rounding of b, and the end
///    tangents h_0, h_{n-1} are far from 0;
///  * not near constant (report.cpp, curvature_range): the segment's
///    curvature range holds its end curvatures
///    k0 = (n-1)/n det(h_0, h_1) / |h_0|^3 and
///    k1 = (n-1)/n det(h_{n-2}, h_{n-1}) / |h_{n-1}|^3, so
///    its turning_deviation is at least |k1 - k0| / 2 * L (L the control
///    polygon's length, as there); it is above `tolerance` with the same
///    margin.
bool violates_where_extremum(const std::vector<Vec2>& b, double tolerance) {
  const std::size_t n = b.size() - 1;
  if (n < 2) return false;
  std::vector<Vec2> h(n);
  double length = 0;
  for (std::size_t i = 0; i < n; ++i) h[i] = b[i + 1] - b[i], length += std::sqrt(dot(h[i], h[i]));
  // The margins: far above the rounding of b, relative to its coordinates.
  double size = 0;
  for (const Vec2 p : b) size = std::max({size, std::abs(p.x), std::abs(p.y)});
  auto one_side = [&](Vec2 u) {
    const double lu = std::sqrt(dot(u, u));
    return lu > 0 && std::all_of(h.begin(), h.end(),
                                 [&](Vec2 v) { return dot(u, v) > kMargin * lu * (std::sqrt(dot(v, v)) + size); });
  };
  if (!one_side(h.front()) && !one_side(h.back()) && !one_side(h.front() + h.back())) return false;
  // The end tangents far from 0 (a handle on its node, or nearly so, leaves
  // the end curvature to the rounding).
  const double l0 = std::sqrt(dot(h.front(), h.front())), l1 = std::sqrt(dot(h.back(), h.back()));
  if (!(l0 > 1e-6 * size && l1 > 1e-6 * size)) return false;
  const double f = (static_cast<double>(n) - 1) / static_cast<double>(n);
  const double k0 = f * det(h[0], h[1]) / (l0 * l0 * l0), k1 = f * det(h[n - 2], h[n - 1]) / (l1 * l1 * l1);
  return std::abs(k1 - k0) / 2 * length > 2 * tolerance + kMargin * (std::abs(k0) + std::abs(k1)) * length;
}

/// Whether `o` has the curvature-extrema gate, whose failures both
/// shortcuts prove.
bool has_extrema_gate(const ReportOptions& o) {
  return std::any_of(o.gates.begin(), o.gates.end(),
                     [](const Gate& g) { return g.kind == Gate::Kind::extrema_at_nodes; });
}

/// Algorithm 1's options for the proofs: monotonicity alone, to o's depth.
ClassifyOptions proof_classify(const ReportOptions& o) {
  ClassifyOptions classify;
  classify.max_depth = o.max_depth;
  classify.inflection = false;
  return classify;
}

/// The proof of a curvature-extrema violation in segment `seg` of `s`
/// (Bezier points `b`): Algorithm 1 finds it not monotone, and
/// violates_where_extremum shows it is neither a cusp nor near constant.
bool extremum_inside(const BSpline& s, const Segment& seg, const std::vector<Vec2>& b, const ClassifyOptions& classify,
                     double tolerance) {
  return classify_segment(s, seg, classify).monotonicity.curvature == Curvature::non_monotone &&
         violates_where_extremum(b, tolerance);
}

}  // namespace

bool straight_bezier(const std::vector<Vec2>& b) {
  const Vec2 v = b.back() - b.front();
  return std::all_of(b.begin(), b.end(), [&](Vec2 p) { return det(p - b.front(), v) == 0; });
}

bool exactly_smooth(const std::vector<Vec2>& p, int m, int k) {
  const Vec2 u = p[static_cast<std::size_t>((k + m - 1) % m)] - p[static_cast<std::size_t>(k)];
  const Vec2 v = p[static_cast<std::size_t>((k + 1) % m)] - p[static_cast<std::size_t>(k)];
  if (u == Vec2(0.0) || v == Vec2(0.0)) return false;
  return det(u, v) == 0 && dot(u, v) < 0;
}

std::optional<Vec2> grid_vector(Vec2 a, double grid) {
  const double gx = a.x / grid, gy = a.y / grid;
  if (gx != std::floor(gx) || gy != std::floor(gy)) return std::nullopt;
  const long dx = std::lround(gx), dy = std::lround(gy), g = std::gcd(std::abs(dx), std::abs(dy));
  if (g == 0) return std::nullopt;
  return Vec2(static_cast<double>(dx / g) * grid, static_cast<double>(dy / g) * grid);
}

std::vector<char> straight_segments(const BSpline& s) {
  std::vector<char> out;
  for (const Segment& seg : s.segments()) out.push_back(straight_bezier(bezier_segment(s, seg).points));
  return out;
}

Rejects extremum_rejects(const BSpline& source, const ReportOptions& o, double grid, Work& work) {
  if (!has_extrema_gate(o) || source.is_rational()) return {};
  const std::vector<char> source_straight = straight_segments(source);
  return [&work, o, grid, source, source_straight](const std::vector<Vec2>& points, const LatticeUnit& u,
                                                   const std::vector<Vec2>& steps) {
    std::vector<char> out(steps.size(), 0);
    const int m = source.unique_point_count(), n = source.segment_count();
    const BSpline at = source.with_points({points.begin(), points.begin() + m});
    // The judged segments: those the unit shapes, straight ones left out
    // (a line that stays one has no extremum; the fix keeps lines so, and a
    // line bent by a step is judged as every candidate is). One run of them,
    // not across the seam (the region's range), else no shortcut.
    std::vector<int> judged;
    for (int i = 0; i < n; ++i) {
      if (source_straight[static_cast<std::size_t>(i)]) continue;
      for (int k : segment_points(at, at.segments()[static_cast<std::size_t>(i)]))
        if (std::find(u.points.begin(), u.points.end(), k % m) != u.points.end()) {
          judged.push_back(i);
          break;
        }
    }
    if (judged.empty() || judged.back() - judged.front() + 1 != static_cast<int>(judged.size())) return out;
    // Each judged segment's Bezier points at `at` and their weights w (a
    // step d moves Bezier point i by w_i d).
    std::vector<Vec2> shifted(at.points().begin(), at.points().begin() + m);
    for (int k : u.points) shifted[static_cast<std::size_t>(k)].x += 1;
    const BSpline unit_x = at.with_points(shifted);
    std::vector<std::vector<Vec2>> base;
    std::vector<std::vector<double>> weight;
    for (int i : judged) {
      const Segment& s = at.segments()[static_cast<std::size_t>(i)];
      base.push_back(bezier_segment(at, s).points);
      const std::vector<Vec2> moved = bezier_segment(unit_x, s).points;
      std::vector<double> w;
      for (std::size_t j = 0; j < moved.size(); ++j) w.push_back(moved[j].x - base.back()[j].x);
      weight.push_back(std::move(w));
    }
    RegionRequest request;
    request.point = u.points.front();
    request.with.assign(u.points.begin() + 1, u.points.end());
    request.each_piece = true;
    request.segments = SegmentRange{judged.front(), judged.back()};
    request.max_depth = o.max_depth;
    request.depth = false;
    const Vec2 anchor = at.points()[static_cast<std::size_t>(u.points.front())];
    // The steps' cells of the grid (every step is a whole number of grid
    // steps: a translation's, or a slide's grid vector's multiples), a view
    // whose pixel centres are the candidates, rendered where that is not
    // many times more pixels than candidates, else each classified alone.
    long i0 = 0, i1 = 0, j0 = 0, j1 = 0;
    for (std::size_t s = 0; s < steps.size(); ++s) {
      const long i = std::lround(steps[s].x / grid), j = std::lround(steps[s].y / grid);
      i0 = s ? std::min(i0, i) : i, i1 = s ? std::max(i1, i) : i;
      j0 = s ? std::min(j0, j) : j, j1 = s ? std::max(j1, j) : j;
    }
    const long width = i1 - i0 + 1, height = j1 - j0 + 1;
    const bool render = width <= kMaxImageSize && height <= kMaxImageSize &&
                        width * height <= 4 * static_cast<long>(steps.size()) + 4096;
    request.width = render ? static_cast<int>(width) : 1;
    request.height = render ? static_cast<int>(height) : 1;
    auto edge = [grid](double a, long cell, double side) { return a + (static_cast<double>(cell) + side) * grid; };
    request.view =
        View{edge(anchor.x, i0, -0.5), edge(anchor.y, j0, -0.5), edge(anchor.x, i1, 0.5), edge(anchor.y, j1, 0.5)};
    try {
      const RegionProblem problem = RegionProblem::make(at, request);
      work.charge(kRegionSetupWork * static_cast<long>(judged.size()));
      std::vector<EachPiece> labels;
      if (render) {
        labels = CpuRegionBackend(1).render(problem).piece_labels;
        work.charge(width * height / kRegionPixelsPerWork + 1);
      }
      for (std::size_t s = 0; s < steps.size(); ++s) {
        const Vec2 p = anchor + steps[s];
        const long i = std::lround(steps[s].x / grid) - i0, j = j1 - std::lround(steps[s].y / grid);
        EachPiece label;
        const int pi = static_cast<int>(i), pj = static_cast<int>(j);
        if (render && pixel_center(*request.view, request.width, request.height, pi, pj) == p) {
          label = labels[static_cast<std::size_t>(j * width + i)];
        } else {
          label = problem.classify(p).piece_label;
          work.charge();
        }
        if (label != EachPiece::fail) continue;
        bool certain = true;
        for (std::size_t q = 0; q < judged.size() && certain; ++q) {
          std::vector<Vec2> b = base[q];
          for (std::size_t k = 0; k < b.size(); ++k) b[k] = b[k] + weight[q][k] * steps[s];
          certain = violates_where_extremum(b, o.constant_tolerance);
        }
        out[s] = certain;
      }
    } catch (const InputError&) {
      return std::vector<char>(steps.size(), 0);  // no shortcut: every step judged
    }
    return out;
  };
}

Judge with_failure_proofs(const BSpline& source, const ReportOptions& o, const RunJudge& runs, Judge passes,
                          Work& work) {
  const bool extrema = has_extrema_gate(o);
  std::vector<double> g2;  // the g2 gates' tolerances
  for (const Gate& g : o.gates)
    if (g.kind == Gate::Kind::g2_at_smooth_nodes) g2.push_back(g.tolerance);
  if ((!extrema && g2.empty()) || source.is_rational()) return passes;
  const int n = source.segment_count();
  // Per segment: straight in the source; the joint at its start judged by
  // g2 wherever the judge passes (C1 by the knots, or a node exactly smooth
  // in the source, which local_judge keeps so).
  const std::vector<char> source_straight = straight_segments(source);
  std::vector<char> smooth_joint;
  for (int i = 0; i < n; ++i) {
    const Segment& right = source.segments()[static_cast<std::size_t>(i)];
    const std::vector<Vec2> r = bezier_segment(source, right).points;
    if (!source.closed() && i == 0) {
      smooth_joint.push_back(0);
      continue;
    }
    const std::vector<Vec2> l =
        bezier_segment(source, source.segments()[static_cast<std::size_t>((i + n - 1) % n)]).points;
    const Vec2 u = l[l.size() - 2] - l.back(), v = r[1] - r.front();
    const bool smooth = u != Vec2(0.0) && v != Vec2(0.0) && det(u, v) == 0 && dot(u, v) < 0;
    smooth_joint.push_back(smooth || source.multiplicity(right.a) < source.degree());
  }
  return [&runs, &work, source, n, source_straight, smooth_joint, extrema, g2, classify = proof_classify(o),
          tolerance = o.constant_tolerance,
          passes = std::move(passes)](const std::vector<Vec2>& from, const std::vector<Vec2>& to) {
    const std::optional<RunJudge::Run> r = runs.run(from, to);
    if (!r) return passes(from, to);
    work.charge();
    const BSpline s = source.with_points({to.begin(), to.begin() + source.unique_point_count()});
    auto segment = [&](int i) -> const Segment& { return s.segments()[static_cast<std::size_t>((i + n) % n)]; };
    for (int q = 0; extrema && q < r->length; ++q) {
      const int i = (r->first + q) % n;
      if (source_straight[static_cast<std::size_t>(i)]) continue;
      if (extremum_inside(s, segment(i), bezier_segment(s, segment(i)).points, classify, tolerance)) return false;
    }
    for (int q = 0; !g2.empty() && q <= r->length; ++q) {
      const int i = (r->first + q) % n;
      if (!smooth_joint[static_cast<std::size_t>(i)]) continue;
      const double kl = certified_end_curvature(s, segment(i - 1), 1), kr = certified_end_curvature(s, segment(i), 0);
      const double scale = std::max(std::abs(kl), std::abs(kr)), jump = std::abs(kl - kr);
      for (const double t : g2)
        if (jump > t * scale * (1 + kMargin) + kMargin * (std::abs(kl) + std::abs(kr))) return false;  // NaN: no
    }
    return passes(from, to);
  };
}

bool proves_extremum_violation(const std::vector<BezierSegment>& before, const BSpline& s, const ReportOptions& o,
                               long& classified) {
  if (!has_extrema_gate(o) || s.is_rational() || static_cast<int>(before.size()) != s.segment_count()) return false;
  const ClassifyOptions classify = proof_classify(o);
  try {
    for (int i = 0; i < s.segment_count(); ++i) {
      const Segment& seg = s.segments()[static_cast<std::size_t>(i)];
      const std::vector<Vec2> b = bezier_segment(s, seg).points;
      if (b == before[static_cast<std::size_t>(i)].points) continue;
      ++classified;
      if (extremum_inside(s, seg, b, classify, o.constant_tolerance)) return true;
    }
  } catch (const InputError&) {
    // A classification that throws proves nothing: the judge decides.
  }
  return false;
}

}  // namespace cmr::report::glyph_detail
