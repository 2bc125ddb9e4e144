// curvature-extrema-at-nodes:runs (report/gates.hpp): the reading of the extremum gate
// for quadratic (TrueType) outlines. A quadratic piece's curvature peaks
// once, at the parabola's vertex, whatever the designer does; what the
// designer places are the on-curve points (nodes) and the off-curve points
// of each run between them, which set how high each piece's peak is. The
// gate asks that along each run (split at inflections) the pieces' peaks
// rise to one highest and fall, and reports each valley piece.
#include <algorithm>
#include <cmath>
#include <set>
#include <optional>
#include <sstream>

#include "spline/curvature.hpp"

#include "report/gates.hpp"
#include "report/report.hpp"
#include "spline/format.hpp"

namespace cmr::report {
namespace {

std::string num(double v, int precision = 6) { return format_number(v, precision); }

/// Control point k (unrolled index) is a node: its polar label is one knot
/// repeated d times, so the curve passes through it.
bool is_node_point(const BSpline& s, int k) {
  const int d = s.degree();
  if (k < 0 || k + d - 1 >= static_cast<int>(s.knots().size())) return false;
  return s.knots()[k] == s.knots()[k + d - 1];
}

/// The off-curve points (distinct indices) of segment `segment`.
void add_handles(const BSpline& s, int segment, std::set<int>& out) {
  const int d = s.degree(), m = s.unique_point_count();
  const int span = s.segments()[segment].span;
  // Its own off-curve points: those whose polar label holds both of the
  // segment's knots (a quadratic's middle point, a cubic's two handles).
  for (int k = span - d + 2; k <= span; ++k)
    if (!is_node_point(s, k)) out.insert(s.closed() ? k % m : k);
}

/// A piece's peak: the largest |kappa| over the segment, at its ends (the
/// certified one-sided curvatures of its joints) or at its interior
/// stationary points (certified roots of lambda).
struct Peak {
  double value = 0;
  double t = 0;
  bool valid = false;
};

}  // namespace

std::vector<GateViolation> unimodal_run_violations(const SplineReport& r) {
  std::vector<GateViolation> out;
  if (!r.spline) return out;
  const BSpline& s = *r.spline;
  const int N = s.segment_count(), d = s.degree();
  const bool closed = s.closed();
  auto wrap = [&](int j) { return closed ? ((j % N) + N) % N : j; };
  // Joint j (0..N-1; 0 is a closed spline's seam, an open spline's ends are
  // run ends) is a node when its knot multiplicity is >= d.
  std::vector<bool> node(N + 1, !closed);
  std::vector<const Joint*> joint(N + 1, nullptr);
  if (closed) node.assign(N + 1, false);
  for (const JointReport& jr : r.joints) {
    const int j = wrap(jr.joint.index);
    joint[j] = &jr.joint;
    node[j] = jr.joint.multiplicity >= d;
  }
  if (closed) node[N] = node[0], joint[N] = joint[0];
  // Inflections split runs: a piece with one inside, or a joint with one.
  std::vector<bool> inflected(N, false), inflection_at(N + 1, false);
  for (const CurveEvent& e : r.inflections) {
    if (e.segment >= 0) inflected[e.segment] = true;
    else if (e.joint >= 0) inflection_at[wrap(e.joint)] = true;
  }
  if (closed) inflection_at[N] = inflection_at[0];
  std::vector<Peak> peak(N);
  for (int i = 0; i < N; ++i) {
    const SpanReport& span = r.spans[i];
    Peak& p = peak[i];
    auto take = [&](double kappa, double t) {
      if (!std::isfinite(kappa)) return;
      p.valid = true;
      if (std::abs(kappa) > p.value) p.value = std::abs(kappa), p.t = t;
    };
    if (joint[i]) take(joint[i]->kappa_right, span.segment.a);
    if (joint[i + 1]) take(joint[i + 1]->kappa_left, span.segment.b);
    if (!joint[i] && !closed) take(curvature_at(s, span.segment.a).kappa, span.segment.a);  // an open spline's ends
    if (!joint[i + 1] && !closed) take(curvature_at(s, span.segment.b).kappa, span.segment.b);
    for (const SpanRoot& root : span.extrema)
      if (root.at == SpanRoot::At::interior) take(root.kappa, root.t);
    if (span.shape.pole || r.cusp) p.valid = false;
  }

  auto joint_text = [&](int j) { return "joint " + std::to_string(closed && j == 0 ? N : j); };
  auto report_valley = [&](int i, int from, int to, bool whole, double left, double right) {
    GateViolation v;
    const Segment& seg = s.segments()[i];
    v.segment = i;
    v.t = peak[i].t;
    v.local_t = (v.t - seg.a) / (seg.b - seg.a);
    std::set<int> handles;
    add_handles(s, i, handles);
    v.handles.assign(handles.begin(), handles.end());
    std::string moves;
    for (int h : v.handles) moves += (moves.empty() ? "" : ", ") + std::to_string(h);
    v.message = "the curvature peak of segment " + std::to_string(i) + " (|kappa| " + num(peak[i].value, 4) +
                " at t = " + num(v.t) + ") is lower than the peaks before (" + num(left, 4) + ") and after (" +
                num(right, 4) + ") it in the run " +
                (whole ? std::string("of the whole contour (no on-curve node)")
                       : "from node " + joint_text(from) + " to node " + joint_text(to)) +
                ": the run's curvature is not unimodal; move control point" + (v.handles.size() == 1 ? " " : "s ") +
                moves + " outwards (or the neighbouring pieces' inwards)";
    out.push_back(std::move(v));
  };
  // One part: consecutive pieces of one run without an inflection. Peaks
  // within kRunPeakTolerance of each other are one plateau; a piece whose
  // peak is below the nearest different peak on both sides is a valley.
  auto judge = [&](const std::vector<int>& part, int from, int to, bool cyclic) {
    std::vector<int> pieces;
    for (int i : part)
      if (peak[i].valid && !r.spans[i].near_constant) pieces.push_back(i);
    const int k = static_cast<int>(pieces.size());
    if (k < 3) return;
    auto differs = [](double a, double b) { return std::abs(a - b) > kRunPeakTolerance * std::max(a, b); };
    std::vector<std::pair<int, int>> valleys;  // (piece position, 0)
    std::vector<std::pair<double, double>> sides;
    for (int a = 0; a < k; ++a) {
      const double v = peak[pieces[a]].value;
      // The nearest different peak before and after (cyclically for a loop).
      auto nearest = [&](int step) -> std::optional<double> {
        for (int b = 1; b < k; ++b) {
          const int c = a + step * b;
          if (!cyclic && (c < 0 || c >= k)) return std::nullopt;
          const double w = peak[pieces[((c % k) + k) % k]].value;
          if (differs(v, w)) return w;
        }
        return std::nullopt;
      };
      const auto before = nearest(-1), after = nearest(+1);
      if (before && after && *before > v && *after > v) {
        // A plateau reports its first piece only.
        if (a > 0 && !differs(v, peak[pieces[a - 1]].value)) continue;
        valleys.push_back({a, 0});
        sides.push_back({*before, *after});
      }
    }
    // A loop's peaks rise and fall once: one valley is its unimodal shape.
    std::size_t skip = cyclic && !valleys.empty() ? 1 : 0;
    for (std::size_t q = skip; q < valleys.size(); ++q)
      report_valley(pieces[valleys[q].first], from, to, cyclic, sides[q].first, sides[q].second);
  };

  int first = 0;
  bool any_node = !closed;
  if (closed)
    for (int j = 0; j < N && !any_node; ++j)
      if (node[j]) first = j, any_node = true;
  std::vector<int> part;
  int run_start = first;
  for (int step = 0; step < N; ++step) {
    const int i = wrap(first + step);
    if (inflected[i]) {  // an inflection inside: the part ends before this piece and restarts after it
      judge(part, run_start, -1, false);
      part.clear();
    } else {
      part.push_back(i);
    }
    const int j = closed ? wrap(i + 1) : i + 1;
    if (node[j] || (closed && !any_node && j == first)) {
      judge(part, run_start, j, !any_node);
      part.clear();
      run_start = j;
    } else if (inflection_at[j]) {
      judge(part, run_start, -1, false);
      part.clear();
    }
  }
  judge(part, run_start, -1, false);
  return out;
}

}  // namespace cmr::report
