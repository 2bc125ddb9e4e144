#include "bezierize/space_analyze.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "numeric/roots.hpp"
#include "bezierize/space_classify.hpp"
#include "spline/fields.hpp"

namespace cmr {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Where p (exact, >= 0 on [0, 1] by construction: |c|^2 or |P'|^2) is 0 on
/// the segment [a, b]: nearest doubles of points of the exact enclosures.
std::vector<double> zeros_on(const Bernstein<Rational>& p, double a, double b) {
  std::vector<double> out;
  for (const RootInterval& r : isolate_roots(p)) {
    const Rational t = r.exact() ? r.lo : Rational((r.lo + r.hi) / 2);
    const Rational u = Rational(a) + t * (Rational(b) - Rational(a));
    const double v = nearest_double(u);
    if (out.empty() || out.back() != v) out.push_back(v);
  }
  return out;
}

double angle_deg(const Point3<Rational>& u, const Point3<Rational>& v) {
  const Point3<Rational> x = cross3(u, v);
  const Rational dp = dot3(u, v);
  if (sgn(x.x) == 0 && sgn(x.y) == 0 && sgn(x.z) == 0 && sgn(dp) > 0) return 0.0;
  return std::atan2(std::sqrt(dot3(x, x).get_d()), dp.get_d()) * (180.0 / std::numbers::pi);
}

/// The terms of one end: legs a, b, c read from the end inwards, and the
/// weights w0..w3 from the end inwards (1 for a polynomial segment).
struct SpaceEnd {
  Point3<Rational> a, b;
  Rational G;   ///< a.a
  Rational A2;  ///< |a x b|^2
  Rational D;   ///< det(a, b, c) (0 for degree 2)
  Point3<Rational> n;  ///< normal of the osculating plane in forward order
  Rational k2;   ///< kappa^2 (0 where G == 0)
  Rational tau;  ///< tau (0 where A2 == 0)
};

/// The end values of a (rational) Bezier segment of degree d (Farin, Curves
/// and Surfaces for CAGD, rational Bezier curves; w == 1 gives the
/// polynomial ones):
///   kappa = (d-1)/d w0 w2 / w1^2 |a x b| / |a|^3,
///   tau   = (d-2)/d w0 w3 / (w1 w2) det(a, b, c) / |a x b|^2
/// (both invariant under reversal of the segment).
SpaceEnd space_end(const std::vector<Point3<Rational>>& B, const std::vector<Rational>& wts, bool at_end) {
  const int d = static_cast<int>(B.size()) - 1;
  const auto q = [&](int k) -> const Point3<Rational>& { return at_end ? B[d - k] : B[k]; };
  const auto w = [&](int k) -> Rational { return wts.empty() ? Rational(1) : wts[at_end ? d - k : k]; };
  SpaceEnd e;
  e.a = q(1) - q(0);
  e.b = q(2) - q(1);
  e.G = dot3(e.a, e.a);
  const Point3<Rational> x = cross3(e.a, e.b);
  e.A2 = dot3(x, x);
  e.D = d >= 3 ? dot3(x, Point3<Rational>(q(3) - q(2))) : Rational(0);
  // Forward order: (b x a) read backwards at a segment's end, (a x b) at its start.
  e.n = at_end ? cross3(e.b, e.a) : x;
  if (sgn(e.G) != 0) {
    const Rational f = Scalar<Rational>::ratio(d - 1, d);
    const Rational om = w(0) * w(2) / (w(1) * w(1));
    e.k2 = f * f * om * om * e.A2 / (e.G * e.G * e.G);
  }
  if (sgn(e.A2) != 0 && d >= 3) e.tau = Scalar<Rational>::ratio(d - 2, d) * w(0) * w(3) / (w(1) * w(2)) * e.D / e.A2;
  return e;
}

/// kappa: kappa^2 exact, one rounding and a square root.
double end_kappa(const SpaceEnd& e) { return sgn(e.G) == 0 ? kNaN : std::sqrt(e.k2.get_d()); }

double end_tau(const SpaceEnd& e) { return sgn(e.A2) == 0 ? kNaN : e.tau.get_d(); }

/// The exact Bezier points of segment s (Cartesian) and, for a rational
/// spline, their weights (empty otherwise).
struct ExactBezier {
  std::vector<Point3<Rational>> points;
  std::vector<Rational> weights;
};

ExactBezier exact_bezier(const SpaceSpline& spline, const Segment& s) {
  const SpaceWindow w = space_window(spline, s);
  ExactBezier b;
  if (spline.is_rational())
    split_homogeneous<Rational>(space_window_bezier<Rational>(w, space_window_hpoints<Rational>(spline, w)), b.points,
                                b.weights);
  else
    b.points = space_window_bezier<Rational>(w, space_window_points<Rational>(spline, w));
  return b;
}

/// lambda3 of segment s in exact arithmetic (rational or not).
Bernstein<Rational> exact_lambda3(const SpaceSpline& spline, const Segment& s) {
  const SpaceWindow w = space_window(spline, s);
  if (spline.is_rational())
    return lambda3_bernstein<Rational>(space_window_bezier<Rational>(w, space_window_hpoints<Rational>(spline, w)));
  return lambda3_bernstein<Rational>(space_window_bezier<Rational>(w, space_window_points<Rational>(spline, w)));
}

/// space_segment for window points made by make_b / make_r (Point3 or, for
/// a rational spline, HPoint3 vectors).
template <class MakeB, class MakeR>
SpaceSegmentResult segment_of(const SpaceWindow& w, const Segment& s, const SpaceAnalyzeOptions& options, MakeB make_b,
                              MakeR make_r) {
  SpaceSegmentResult r;
  const SpaceDecision c = space_decide(w, SpaceQuantity::curvature, options.max_depth, make_b, make_r);
  r.curvature = c.result;
  r.exact_used = c.exact_used;
  const auto Bb = space_window_bezier<Bounded>(w, make_b());
  const SpacePolynomials<Bounded> pb = space_polynomials<Bounded>(Bb);
  using ExactPoints = decltype(space_window_bezier<Rational>(w, make_r()));
  std::optional<ExactPoints> Br;
  const auto exact = [&]() -> const ExactPoints& {
    if (!Br) Br = space_window_bezier<Rational>(w, make_r());
    return *Br;
  };
  if (strict_sign(pb.c2) != 1) {
    const SpacePolynomials<Rational> pr = space_polynomials<Rational>(exact());
    if (is_zero(pr.c2)) r.straight = true;
    else r.zero_curvature = zeros_on(pr.c2, s.a, s.b);
  }
  if (strict_sign(pb.g) != 1) {
    const Bernstein<Rational> g = space_speed2_bernstein<Rational>(exact());
    r.cusp = is_zero(g) || !isolate_roots(g).empty();
  }
  if (options.torsion) {
    const SpaceDecision t = space_decide(w, SpaceQuantity::torsion, options.max_depth, make_b, make_r);
    r.torsion = t.result;
    r.exact_used = r.exact_used || t.exact_used;
    const Bernstein<Bounded> nb = torsion_numerator_bernstein<Bounded>(Bb);
    r.torsion_sign = strict_sign(nb);
    if (r.torsion_sign == 0 && !nb.empty()) {
      const Bernstein<Rational> N = torsion_numerator_bernstein<Rational>(exact());
      r.torsion_sign = strict_sign(N);
      if (r.torsion_sign == 0 && !is_zero(N)) {
        const std::vector<RootInterval> roots = isolate_roots(N);
        // No root on the closed span: N has one strict sign there, its sign
        // at the start (the coefficients' signs need not show it).
        if (roots.empty()) r.torsion_sign = sign_at_start(N);
        for (const RootInterval& root : roots) {
          if (!root.sign_change() || (root.exact() && (sgn(root.lo) == 0 || root.lo == 1))) continue;
          const Rational u = root.exact() ? root.lo : Rational((root.lo + root.hi) / 2);
          r.torsion_sign_changes.push_back(nearest_double(Rational(Rational(s.a) + u * (Rational(s.b) - Rational(s.a)))));
        }
      }
    }
  }
  return r;
}

}  // namespace

SpaceSegmentResult space_segment(const SpaceSpline& spline, const Segment& s, const SpaceAnalyzeOptions& options) {
  const SpaceWindow w = space_window(spline, s);
  SpaceSegmentResult r =
      spline.is_rational()
          ? segment_of(
                w, s, options, [&] { return space_window_hpoints<Bounded>(spline, w); },
                [&] { return space_window_hpoints<Rational>(spline, w); })
          : segment_of(
                w, s, options, [&] { return space_window_points<Bounded>(spline, w); },
                [&] { return space_window_points<Rational>(spline, w); });
  if (r.torsion) {
    // N == 0 exactly: torsion_sign 0 with no sign change and class constant.
    r.planar = r.torsion->curvature == Curvature::constant && r.torsion_sign == 0 && r.torsion_sign_changes.empty();
    if (!r.planar && options.torsion_tolerance > 0) {
      bool within = true;
      for (int i = 0; i <= kTorsionSamples + 1 && within; ++i) {
        const double tau = space_torsion(spline, s.a + (s.b - s.a) * i / (kTorsionSamples + 1));
        within = !std::isfinite(tau) || std::abs(tau) <= options.torsion_tolerance;  // kappa = 0: no torsion there
      }
      if (within) {
        r.planar = true;
        r.torsion->curvature = Curvature::constant;
        r.torsion_sign = 0;
        r.torsion_sign_changes.clear();
      }
    }
  }
  return r;
}

std::vector<SpaceExtremum> space_curvature_extrema(const SpaceSpline& spline, const Segment& s) {
  const Bernstein<Rational> l = exact_lambda3(spline, s);
  std::vector<SpaceExtremum> out;
  if (is_zero(l)) return out;
  for (const RootInterval& r : isolate_roots(l)) {
    if (!r.sign_change() || (r.exact() && (sgn(r.lo) == 0 || r.lo == 1))) continue;  // inside only
    const Rational t = r.exact() ? r.lo : Rational((r.lo + r.hi) / 2);
    out.push_back({nearest_double(Rational(Rational(s.a) + t * (Rational(s.b) - Rational(s.a)))), r.sign_before > 0});
  }
  return out;
}

SpaceJoint space_joint(const SpaceSpline& spline, int left, int right, const ContinuityTolerances& tolerances) {
  const Segment& L = spline.segments()[static_cast<std::size_t>(left)];
  const Segment& R = spline.segments()[static_cast<std::size_t>(right)];
  const int d = spline.degree();
  SpaceJoint j;
  j.index = right == 0 ? spline.segment_count() : right;
  j.knot = right == 0 ? L.b : R.a;
  j.multiplicity = spline.multiplicity(R.a);
  j.continuity = d - j.multiplicity;
  const ExactBezier bl = exact_bezier(spline, L), br = exact_bezier(spline, R);
  const SpaceEnd l = space_end(bl.points, bl.weights, true), r = space_end(br.points, br.weights, false);
  j.kappa_left = end_kappa(l);
  j.kappa_right = end_kappa(r);
  j.tau_left = end_tau(l);
  j.tau_right = end_tau(r);
  j.zero_tangent = sgn(l.G) == 0 || sgn(r.G) == 0;
  if (j.zero_tangent) {
    j.angle_deg = j.normal_angle_deg = kNaN;
    return j;
  }
  // sign(kappa_R - kappa_L) = sign(kappa_R^2 - kappa_L^2), exact.
  if (j.continuity < 2) j.jump = sgn(Rational(r.k2 - l.k2));
  // sign(tau_R - tau_L) where both kappa > 0, exact.
  if (j.continuity < 3 && sgn(l.A2) > 0 && sgn(r.A2) > 0) j.torsion_jump = sgn(Rational(r.tau - l.tau));
  j.angle_deg = j.continuity >= 1 ? 0.0 : angle_deg(Point3<Rational>(Rational(0) - l.a.x, Rational(0) - l.a.y,
                                                                    Rational(0) - l.a.z),
                                                    r.a);
  j.normal_angle_deg = sgn(l.A2) == 0 || sgn(r.A2) == 0 ? kNaN : (j.continuity >= 2 ? 0.0 : angle_deg(l.n, r.n));
  j.g1 = j.angle_deg <= tolerances.angle_deg;
  const double diff = std::fabs(j.kappa_right - j.kappa_left);
  const double scale = std::max(j.kappa_left, j.kappa_right);
  const bool same_kappa = j.continuity >= 2 || (j.continuity >= 1 && j.jump == 0) || diff <= tolerances.curvature_rel * scale;
  const bool same_plane = std::isnan(j.normal_angle_deg) || j.normal_angle_deg <= tolerances.angle_deg;
  j.g2 = j.g1 && same_kappa && same_plane;
  return j;
}

namespace {

Joint as_joint(const SpaceJoint& s, bool torsion) {
  Joint j;
  j.index = s.index;
  j.jump = torsion ? s.torsion_jump : s.jump;
  return j;
}

SegmentClass as_class(const SpaceSegmentResult& s, bool torsion) {
  SegmentClass c = neutral_class();
  c.monotonicity = torsion ? s.torsion.value_or(MonotonicityResult{}) : s.curvature;
  return c;
}

}  // namespace

Direction space_verdict(const SpaceSpline& spline, const std::vector<SpaceSegmentResult>& segments,
                        const std::vector<SpaceJoint>& joints, const std::optional<SpaceJoint>& seam, bool torsion,
                        std::vector<int>* conflicts) {
  (void)spline;
  std::vector<SegmentClass> classes;
  std::vector<Joint> js;
  for (const SpaceSegmentResult& s : segments) classes.push_back(as_class(s, torsion));
  for (const SpaceJoint& j : joints) js.push_back(as_joint(j, torsion));
  int last = static_cast<int>(classes.size());
  if (seam) {  // the seam as the joint before a neutral class appended at the end (analyze.hpp)
    classes.push_back(neutral_class());
    js.push_back(as_joint(*seam, torsion));
    ++last;
  }
  return part_verdict(classes, js, 0, last, Mode::cmrwi, conflicts);
}

SpaceAnalysis analyze_space(const SpaceSpline& spline, const SpaceAnalyzeOptions& options) {
  if (options.max_depth < 0 || options.max_depth > kMaxDepth)
    throw InputFieldError(field("max_depth") + " " + std::to_string(options.max_depth) + " is outside 0.." +
                          std::to_string(kMaxDepth));
  validate(options.continuity);
  if (!(options.torsion_tolerance >= 0 && std::isfinite(options.torsion_tolerance)))
    throw InputFieldError(field("torsion_tolerance") + " " + std::to_string(options.torsion_tolerance) +
                          " is not a number >= 0");
  SpaceAnalysis a;
  const int N = spline.segment_count();
  for (const Segment& s : spline.segments()) {
    a.segments.push_back(space_segment(spline, s, options));
    const SpaceSegmentResult& r = a.segments.back();
    a.exact_segments += r.exact_used ? 1 : 0;
    a.cusp = a.cusp || r.cusp;
    a.zero_curvature = a.zero_curvature || !r.zero_curvature.empty();
  }
  for (int i = 1; i < N; ++i) a.joints.push_back(space_joint(spline, i - 1, i, options.continuity));
  if (spline.closed()) a.seam = space_joint(spline, N - 1, 0, options.continuity);
  a.curvature = space_verdict(spline, a.segments, a.joints, a.seam, false, &a.joint_conflicts);
  if (options.torsion) {
    a.torsion = space_verdict(spline, a.segments, a.joints, a.seam, true);
    a.planar = !a.segments.empty();
    for (const SpaceSegmentResult& r : a.segments) a.planar = a.planar && r.planar;
    // Constant pieces go with either direction (the planar rules, as a curve
    // of straights): the jumps of a torsion that is noise do not count.
    if (a.planar) a.torsion = Direction::increasing;
  }
  return a;
}

}  // namespace cmr
