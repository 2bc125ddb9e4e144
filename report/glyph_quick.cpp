// The grid descent's measures (glyph_quick.hpp).
#include "report/glyph_quick.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bezierize/extract.hpp"
#include "report/batch.hpp"
#include "report/glyph_settle.hpp"

namespace cmr::report::glyph_detail {

double g2_excess(double kl, double kr, double tol, double size) {
  const double scale = std::max(std::abs(kl), std::abs(kr));
  if (!(scale > 0) || !std::isfinite(scale)) return 0;
  if (kl == 0 || kr == 0) return scale * size / (1 + scale * size);
  return std::max(0.0, std::abs(kl - kr) / scale - tol);
}

Badness badness_of(const SplineReport& r, const ReportOptions& o, double size) {
  Badness b;
  if (o.require && !r.requirement_pass) b.count += 1, b.excess += 1;
  for (const GateResult& g : r.gates)
    for (const GateViolation& v : g.violations) {
      if (v.info) continue;
      ++b.count;
      double e = 1;
      if (v.segment >= 0 && v.local_t > 0 && v.local_t < 1) e = std::min(v.local_t, 1 - v.local_t);
      if (g.gate.kind == Gate::Kind::g2_at_smooth_nodes && v.joint >= 0)
        for (const JointReport& jr : r.joints)
          if (jr.joint.index == v.joint) {
            const double kl = jr.joint.kappa_left, kr = jr.joint.kappa_right;
            const double scale = std::max(std::abs(kl), std::abs(kr));
            if (scale > 0 && std::isfinite(scale)) e = g2_excess(kl, kr, g.gate.tolerance, size);
            break;
          }
      b.excess += e;
    }
  return b;
}

std::optional<QuickJudge> quick_judge_of(const BSpline& s, const ReportOptions& o) {
  if (o.require || s.is_rational()) return std::nullopt;
  QuickJudge q;
  for (const Gate& g : o.gates) {
    if (g.kind == Gate::Kind::extrema_at_nodes) {
      q.extrema = true;
    } else if (g.kind == Gate::Kind::g2_at_smooth_nodes) {
      q.g2 = true;
      q.tolerance = g.tolerance;
    } else {
      return std::nullopt;
    }
  }
  const SplineReport r = gate_report(s, o);
  const int n = s.segment_count();
  q.g2_joint.assign(n, 0);
  q.line_start = q.line_end = straight_segments(s);
  q.size = curve_size(s);
  for (const JointReport& jr : r.joints)
    if (!jr.corner && std::isfinite(jr.joint.kappa_left) && std::isfinite(jr.joint.kappa_right))
      q.g2_joint[jr.joint.index % n] = 1;
  return q;
}

double bezier_kappa(const std::vector<Vec2>& b, double t) {
  const int d = static_cast<int>(b.size()) - 1;
  auto eval = [t](std::vector<Vec2> p) {
    for (std::size_t r = 1; r < p.size(); ++r)
      for (std::size_t k = 0; k + r < p.size(); ++k) p[k] = (1 - t) * p[k] + t * p[k + 1];
    return p.empty() ? Vec2(0.0) : p[0];
  };
  std::vector<Vec2> d1, d2;
  for (int k = 0; k < d; ++k) d1.push_back(static_cast<double>(d) * (b[k + 1] - b[k]));
  for (int k = 0; k + 1 < d; ++k) d2.push_back(static_cast<double>(d - 1) * (d1[k + 1] - d1[k]));
  const Vec2 v = eval(d1), a = eval(d2);
  const double speed = std::hypot(v.x, v.y);
  return speed > 0 ? (v.x * a.y - v.y * a.x) / (speed * speed * speed) : std::numeric_limits<double>::quiet_NaN();
}

Badness quick_badness(const BSpline& s, const QuickJudge& q) {
  Badness b;
  const std::vector<BezierSegment> segs = bezier_segments(s);
  const int n = static_cast<int>(segs.size());
  std::vector<double> k0(n), k1(n);
  for (int i = 0; i < n; ++i) {
    std::vector<double> k(kQuickSamples + 1);
    for (int j = 0; j <= kQuickSamples; ++j)
      k[j] = bezier_kappa(segs[i].points, static_cast<double>(j) / kQuickSamples);
    k0[i] = k.front(), k1[i] = k.back();
    if (!q.extrema) continue;
    double span = 0;
    for (double v : k) span = std::max(span, std::abs(v));
    int last = 0;
    for (int j = 0; j < kQuickSamples; ++j) {
      const double dk = k[j + 1] - k[j];
      if (!std::isfinite(dk)) continue;
      if (std::abs(dk) <= 1e-12 * span) continue;  // flat (a line): no extremum
      const int sign = dk > 0 ? 1 : -1;
      if (last != 0 && sign != last) {
        const double lt = static_cast<double>(j) / kQuickSamples;
        ++b.count;
        b.excess += std::min(lt, 1 - lt);
      }
      last = sign;
    }
  }
  if (q.g2)
    for (int i = 0; i < n; ++i) {
      if (i >= static_cast<int>(q.g2_joint.size()) || !q.g2_joint[i]) continue;
      const int left = i > 0 ? i - 1 : (s.closed() ? n - 1 : -1);
      if (left < 0) continue;
      double kl = k1[left], kr = k0[i];
      // A line's side: exactly 0 (its Bezier points are exactly collinear).
      if (q.line_end[left]) kl = 0;
      if (q.line_start[i]) kr = 0;
      const double scale = std::max(std::abs(kl), std::abs(kr));
      if (!(scale > 0) || !std::isfinite(scale)) continue;
      if (std::abs(kl - kr) <= 0.9 * q.tolerance * scale) continue;
      ++b.count;
      b.excess += g2_excess(kl, kr, 0.9 * q.tolerance, q.size);
    }
  return b;
}

}  // namespace cmr::report::glyph_detail
