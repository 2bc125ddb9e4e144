#include "report/report.hpp"

#include <algorithm>
#include <charconv>
#include <functional>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "numeric/bernstein.hpp"
#include "bezierize/extract.hpp"
#include "design/fix.hpp"
#include "numeric/fast_roots.hpp"
#include "numeric/tracked.hpp"
#include "bezierize/joint_json.hpp"
#include "bezierize/lambda.hpp"
#include "bezierize/rational_lambda.hpp"
#include "region/region.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/parallel.hpp"
#include "spline/spline_json.hpp"
#include "draw/draw.hpp"
#include "draw/svg_text.hpp"
#include "io/output.hpp"
#include "report/extremum.hpp"

namespace cmr::report {

Requirement parse_requirement(const std::string& text) {
  if (text == "cmrwi") return {Mode::cmrwi, std::nullopt};
  if (text == "cmr") return {Mode::cmr, std::nullopt};
  if (text.rfind("split:", 0) == 0) {
    std::string s = text.substr(6);
    Extremum extremum = Extremum::any;
    for (const auto& [suffix, e] : {std::pair{std::string(":sharpest"), Extremum::sharpest},
                                    std::pair{std::string(":flattest"), Extremum::flattest}})
      if (s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0) {
        extremum = e;
        s.resize(s.size() - suffix.size());
      }
    for (const char* old : {":max", ":min"})
      if (s.size() > 4 && s.compare(s.size() - 4, 4, old) == 0)
        throw InputFieldError(field("require") + ": '" + text +
                              "' read signed curvature, which flips with the direction of travel: " + "use split:" +
                              s.substr(0, s.size() - 4) + ":sharpest or :flattest (by |curvature|)");
    int joint = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), joint);
    if (ec == std::errc() && end == s.data() + s.size() && !s.empty()) return {Mode::cmrwi, joint, extremum};
  }
  throw InputFieldError(field("require") + ": '" + text +
                        "' is not cmrwi, cmr, split:S, split:S:sharpest or split:S:flattest (S a joint index)");
}

std::string to_string(const Requirement& r) {
  if (r.split)
    return "split:" + std::to_string(*r.split) +
           (r.extremum == Extremum::sharpest ? ":sharpest" : r.extremum == Extremum::flattest ? ":flattest" : "");
  return r.mode == Mode::cmr ? "cmr" : "cmrwi";
}

bool split_passes(Split verdict, Extremum extremum, const Joint& joint) {
  const std::optional<ExtremumKind> kind = split_extremum_kind(verdict, joint);
  switch (extremum) {
    case Extremum::sharpest: return kind == ExtremumKind::sharpest;
    case Extremum::flattest: return kind == ExtremumKind::flattest;
    case Extremum::any: return verdict == Split::inc_dec || verdict == Split::dec_inc;
  }
  return false;
}

Requirement check_of(const ReportOptions& options) { return options.require.value_or(Requirement{}); }

namespace {

bool monotone(Direction d) { return d == Direction::increasing || d == Direction::decreasing; }

bool passes(const SplineAnalysis& a, const Requirement& check) {
  if (check.split) return a.split && split_passes(*a.split, check.extremum, a.joints[*check.split - 1]);
  return monotone(check.mode == Mode::cmr ? a.cmr : a.cmrwi);
}

AnalyzeOptions analyze_options(const ReportOptions& options) {
  AnalyzeOptions ao;
  ao.classify.max_depth = options.max_depth;
  ao.split = check_of(options).split;
  ao.split_mode = Mode::cmrwi;
  ao.continuity = options.continuity;
  ao.segments = options.segments;
  return ao;
}

// Point, tangent and curvature of a Bezier segment at u (de Casteljau down to
// three points, whose differences give the first two derivatives).
struct Frame {
  Vec2 point{0.0}, tangent{0.0};
  double kappa = 0;
  double weight = 1;  ///< W(u) of a rational segment (its sign tells the sides of a pole apart)
  bool drawn = true;  ///< drawable (CurveSampler::inside): false near a pole, where the curve runs off
};

Frame frame_at(const std::vector<Vec2>& B, double u);

/// A rational Bezier segment (homogeneous points H = (W x, W y, W)): from the
/// homogeneous curve and its derivatives at u, C' = h / W^2 with
/// h = W X' - W' X and kappa = W^3 det(H, H', H'') / |h|^3 (rational_lambda.hpp).
/// Where W(u) = 0 (a pole) the point is not finite: Frame::drawn is false.
Frame frame_at(const std::vector<Vec2>& B, const std::vector<glm::dvec3>& H, double u) {
  if (H.empty()) return frame_at(B, u);
  glm::dvec3 d[3];  // H, H', H'' at u from the Bernstein derivatives
  for (int r = 0; r < 3; ++r) {
    std::vector<glm::dvec3> c = H;
    for (int k = 0; k < r; ++k) {
      for (std::size_t i = 0; i + 1 < c.size(); ++i) c[i] = double(c.size() - 1) * (c[i + 1] - c[i]);
      c.pop_back();
    }
    for (std::size_t m = 1; m < c.size(); ++m)
      for (std::size_t i = 0; i + m < c.size(); ++i) c[i] = (1 - u) * c[i] + u * c[i + 1];
    d[r] = c[0];
  }
  const Vec2 X(d[0].x, d[0].y), X1(d[1].x, d[1].y);
  const Vec2 h = d[0].z * X1 - d[1].z * X;
  const double D = glm::dot(d[0], glm::cross(d[1], d[2]));
  const double len = std::sqrt(dot(h, h)), w = d[0].z;
  return {X / w, h / (w * w), w * w * w * D / (len * len * len), w};
}

Frame frame_at(const std::vector<Vec2>& B, double u) {
  const int n = static_cast<int>(B.size()) - 1;
  std::vector<Vec2> w = B;
  for (int r = 1; r <= n - 2; ++r)
    for (int i = 0; i + r <= n; ++i) w[i] = (1 - u) * w[i] + u * w[i + 1];
  const Vec2 a = w[1] - w[0], b = w[2] - w[1];
  const Vec2 d1 = double(n) * ((1 - u) * a + u * b);
  const Vec2 d2 = double(n) * (n - 1) * (b - a);
  const Vec2 l = (1 - u) * w[0] + u * w[1], r = (1 - u) * w[1] + u * w[2];
  const double speed = std::sqrt(dot(d1, d1));
  return {(1 - u) * l + u * r, d1, det(d1, d2) / (speed * speed * speed)};
}

// Curvature of a Bezier segment with exact points at parameter u: exact
// P'(u), P''(u) from the Bernstein derivatives of the coordinates
// (numeric/bernstein.hpp), then det and |P'|^2 rounded once each, so the
// sign is exact and the relative error a few units of rounding (within
// kKappaRelError). NaN where P'(u) = 0.
double exact_kappa(const std::vector<Point<Rational>>& B, const Rational& u) {
  const int n = static_cast<int>(B.size()) - 1;
  Bernstein<Rational> x, y;
  for (const Point<Rational>& p : B) x.push_back(p.x), y.push_back(p.y);
  const Bernstein<Rational> x1 = bernstein_derivative(x), y1 = bernstein_derivative(y);
  const Rational n1(n), n2(n * (n - 1));
  const Point<Rational> d1(bernstein_eval(x1, u) / n1, bernstein_eval(y1, u) / n1);  // P'/n
  const Point<Rational> d2(bernstein_eval(bernstein_derivative(x1), u) / n2,
                           bernstein_eval(bernstein_derivative(y1), u) / n2);  // P''/(n(n-1))
  const Rational G = dot(d1, d1);
  if (sgn(G) == 0) return std::numeric_limits<double>::quiet_NaN();
  const double A = Rational(det(d1, d2)).get_d(), g = G.get_d();
  return (n - 1.0) / n * A / g / std::sqrt(g);
}

// Curvature of a rational Bezier segment with exact homogeneous points at u:
// kappa = W^3 D / |h|^3 (bezierize/rational_lambda.hpp) with W, D and h
// evaluated exactly, rounded once each (sign exact, within kKappaRelError).
// NaN where h(u) = 0 (a zero tangent).
double exact_rational_kappa(const std::vector<HPoint<Rational>>& H, const Rational& u) {
  const HomogeneousBezier<Rational> c = homogeneous_components<Rational>(H);
  const Bernstein<Rational> D = rational_d_bernstein(c);
  const auto h = rational_h_bernstein(c);
  const auto at = [&](const Bernstein<Rational>& p) { return p.empty() ? Rational(0) : bernstein_eval(p, u); };
  const Rational w = at(c.w), hx = at(h[0]), hy = at(h[1]);
  const Rational hh = hx * hx + hy * hy;
  if (sgn(hh) == 0) return std::numeric_limits<double>::quiet_NaN();
  const double num = Rational(w * w * w * at(D)).get_d(), g = hh.get_d();
  return num / g / std::sqrt(g);
}

// Roots of p in segment s, each with the curvature at its enclosure's
// midpoint (kappa_at: exact_kappa or exact_rational_kappa of the segment).
std::vector<SpanRoot> span_roots(const Bernstein<Rational>& p, const Segment& s,
                                 const std::function<double(const Rational&)>& kappa_at, const RootOptions& options) {
  const Rational a(s.a), len = Rational(s.b) - Rational(s.a);
  std::vector<SpanRoot> out;
  for (const RootInterval& r : isolate_roots(p, options)) {
    SpanRoot sr;
    const Rational mid = (r.lo + r.hi) / 2;
    sr.t = nearest_double(a + mid * len);
    sr.t_lo = double_below(a + r.lo * len);
    sr.t_hi = double_above(a + r.hi * len);
    sr.exact = r.exact();
    sr.multiplicity = r.multiplicity;
    sr.sign_before = r.sign_before;
    sr.sign_after = r.sign_after;
    if (r.exact() && sgn(r.lo) == 0)
      sr.at = SpanRoot::At::start;
    else if (r.exact() && r.lo == 1)
      sr.at = SpanRoot::At::end;
    sr.kappa = kappa_at(mid);
    out.push_back(sr);
  }
  return out;
}

// a + x * len as a double when it is exact in double (x, a, len exact).
bool exact_affine(double a, double len, double x, double& out) {
  const double p = x * len;
  if (p != 0 ? !(std::fabs(p) >= Tracked::kSafe && std::isfinite(p) && std::fma(x, len, -p) == 0) : !(x == 0 || len == 0))
    return false;
  const double r = a + p;
  if (!std::isfinite(r)) return false;
  const double bb = r - a;
  if ((a - (r - bb)) + (p - bb) != 0) return false;
  out = r;
  return true;
}

// exact_kappa of a segment given by exactness-tracked Bezier points: the same
// formula on error-bounded values; nullopt when they are not tight enough to
// certify kKappaRelError (then the exact evaluation runs).
std::optional<double> tracked_kappa(const std::vector<Point<Tracked>>& B, double u) {
  const int n = static_cast<int>(B.size()) - 1;
  Bernstein<Tracked> x, y;
  for (const Point<Tracked>& p : B) x.push_back(p.x), y.push_back(p.y);
  const Bernstein<Tracked> x1 = bernstein_derivative(x), y1 = bernstein_derivative(y);
  const Tracked n1(n), n2(n * (n - 1)), tu(u);
  const Point<Tracked> d1(bernstein_eval(x1, tu) / n1, bernstein_eval(y1, tu) / n1);
  const Point<Tracked> d2(bernstein_eval(bernstein_derivative(x1), tu) / n2,
                          bernstein_eval(bernstein_derivative(y1), tu) / n2);
  const Tracked G = dot(d1, d1), A = det(d1, d2);
  if (G.v == 0 && G.e == 0) return std::numeric_limits<double>::quiet_NaN();
  const auto tight = [](const Tracked& v) { return (v.v == 0 && v.e == 0) || v.e <= 0x1p-40 * std::fabs(v.v); };
  if (!(G.v > 0 && tight(G) && tight(A))) return std::nullopt;
  return (n - 1.0) / n * (A.v + 0.0) / G.v / std::sqrt(G.v);  // an exact zero as +0, as exact_kappa gives it
}

// span_roots from isolate_roots_bounded's roots (the same enclosures), the
// curvature from tracked_kappa where it certifies, else kappa_exact.
std::vector<SpanRoot> fast_span_roots(const std::vector<FastRoot>& roots, const Segment& s,
                                      const std::vector<Point<Tracked>>& B,
                                      const std::function<double(const Rational&)>& kappa_exact) {
  std::vector<SpanRoot> out;
  const double len = s.b - s.a;
  const bool len_exact = [&] {
    const double bb = len - s.b;  // TwoSum of s.b + (-s.a)
    return std::isfinite(len) && (s.b - (len - bb)) + (-s.a - bb) == 0;
  }();
  for (const FastRoot& r : roots) {
    SpanRoot sr;
    const double lo = r.lo(), hi = r.hi(), mid = r.mid();
    double t = 0, tl = 0, th = 0;
    if (len_exact && exact_affine(s.a, len, mid, t) && exact_affine(s.a, len, lo, tl) && exact_affine(s.a, len, hi, th)) {
      sr.t = t, sr.t_lo = tl, sr.t_hi = th;
    } else {
      const Rational a(s.a), l = Rational(s.b) - Rational(s.a);
      sr.t = nearest_double(a + Rational(mid) * l);
      sr.t_lo = double_below(a + Rational(lo) * l);
      sr.t_hi = double_above(a + Rational(hi) * l);
    }
    sr.exact = r.exact;
    sr.multiplicity = r.multiplicity;
    sr.sign_before = r.sign_before;
    sr.sign_after = r.sign_after;
    if (r.exact && r.k == 0) sr.at = SpanRoot::At::start;
    else if (r.exact && lo == 1) sr.at = SpanRoot::At::end;
    const std::optional<double> k = tracked_kappa(B, mid);
    sr.kappa = k ? *k : kappa_exact(Rational(mid));
    out.push_back(sr);
  }
  return out;
}

// The curve as a sequence of stretches on which a sign (of dkappa/ds, or of
// kappa) is constant, each with the place where it ends; the events are the
// places where the sign changes.
struct Place {
  double t = 0;
  int segment = -1, joint = -1;  // inside a segment, on a joint, or (both -1) the domain end
  double kappa = 0;
};
struct Stretch {
  int sign = 0;
  Place end;
};

void add_span_stretches(std::vector<Stretch>& out, int start_sign, const std::vector<SpanRoot>& roots, int segment,
                        const Place& end) {
  int sign = start_sign;
  for (const SpanRoot& r : roots) {
    if (r.at != SpanRoot::At::interior) continue;  // roots at the ends leave the sign inside the span alone
    out.push_back({r.sign_before, {r.t, segment, -1, r.kappa}});
    sign = r.sign_after;
  }
  out.push_back({sign, end});
}

struct SignChange {
  Place at;
  int before = 0, after = 0;
};

std::vector<SignChange> sign_changes(const std::vector<Stretch>& stretches) {
  std::vector<SignChange> out;
  int current = 0;
  Place at;
  // A stretch of sign 0 (a pole) breaks the chain: no change across it.
  for (const Stretch& s : stretches) {
    if (current != 0 && s.sign != 0 && s.sign != current) out.push_back({at, current, s.sign});
    current = s.sign;
    at = s.end;
  }
  return out;
}

/// Exact Bezier points of each segment, computed when first needed: lambda
/// and eta formed from them are exact polynomials of the spline's double
/// data, so their roots are certain.
class ExactPoints {
 public:
  explicit ExactPoints(const BSpline& spline) : spline_(spline), points_(spline.segment_count()) {}
  /// Cartesian Bezier points of a polynomial spline's segment i (a rational
  /// one uses homogeneous(i): no division by a weight that may vanish).
  const std::vector<Point<Rational>>& operator()(int i) {
    CMR_CHECK(!spline_.is_rational());
    if (!points_[i]) points_[i] = segment_bezier_points<Rational>(spline_, spline_.segments()[i]);
    return *points_[i];
  }
  /// Homogeneous Bezier points of a rational spline's segment i.
  std::vector<HPoint<Rational>> homogeneous(int i) const {
    return segment_homogeneous_points<Rational>(spline_, spline_.segments()[i]);
  }

 private:
  const BSpline& spline_;
  std::vector<std::optional<std::vector<Point<Rational>>>> points_;
};

/// Signs of lambda and eta just right of a segment's start.
struct StartSigns {
  int lambda = 0, eta = 0;
};

/// One segment's report: its Bezier points, class, and the roots of lambda
/// and eta. Most segments' lambda or eta has coefficients of one certain
/// sign, so no root; the error-bounded points show that without rational
/// arithmetic, and only the others are formed exactly.
SpanReport span_report(const BSpline& spline, int i, const SegmentClass& c, const SegmentShape& shape,
                       const RootOptions& roots, ExactPoints& exact, StartSigns& start) {
  const Segment& s = spline.segments()[i];
  SpanReport span{s, {}, {}, c, shape, false, false, {}, {}};
  // lambda and eta (for a rational spline: lambda and D of rational_lambda.hpp).
  Bernstein<Bounded> lambda_b, eta_b;
  std::function<Bernstein<Rational>()> lambda_exact, eta_exact;
  std::function<double(const Rational&)> kappa_at;
  if (spline.is_rational()) {
    const auto H = segment_homogeneous_points<Bounded>(spline, s);
    for (const HPoint<Bounded>& h : H) {
      // Bezier points; a zero weight (possible at a pole) leaves NaN, which
      // nothing draws (Frame::drawn) and JSON writes as null.
      span.bezier.push_back(h.z.v != 0 ? Vec2(h.x.v / h.z.v, h.y.v / h.z.v) : Vec2(std::numeric_limits<double>::quiet_NaN()));
      span.homogeneous.push_back({h.x.v, h.y.v, h.z.v});
    }
    // A pole: no extrema or inflections to speak of (start signs 0 break the
    // chains of find_events there).
    if (shape.pole) return span;
    lambda_b = rational_lambda_bernstein<Bounded>(H);
    eta_b = rational_d_bernstein<Bounded>(H);
    lambda_exact = [&] { return rational_lambda_bernstein<Rational>(exact.homogeneous(i)); };
    eta_exact = [&] { return rational_d_bernstein<Rational>(exact.homogeneous(i)); };
    kappa_at = [&](const Rational& u) { return exact_rational_kappa(exact.homogeneous(i), u); };
  } else {
    // Exactness-tracked (tracked.hpp): the same values as Bounded with
    // bounds that stay 0 where the arithmetic was exact.
    const auto B = segment_bezier_points<Tracked>(spline, s);
    for (const Point<Tracked>& p : B) span.bezier.push_back({p.x.v, p.y.v});
    lambda_b = to_bounded(lambda_bernstein<Tracked>(B));
    eta_b = to_bounded(eta_bernstein<Tracked>(B));
    lambda_exact = [&] { return lambda_bernstein<Rational>(exact(i)); };
    eta_exact = [&] { return eta_bernstein<Rational>(exact(i)); };
    kappa_at = [&](const Rational& u) { return exact_kappa(exact(i), u); };
    if (fast_paths_enabled()) {
      // Roots by certified float isolation (fast_roots.hpp): the exact
      // isolation's enclosures wherever every sign it reads is certain.
      const auto fast = [&](const Bernstein<Bounded>& p, bool& zero, int& sign, std::vector<SpanRoot>& out) {
        sign = strict_sign(p);
        if (sign != 0) return true;
        if (std::all_of(p.begin(), p.end(), [](const Bounded& x) { return x.v == 0 && x.e == 0; })) {
          zero = true;  // certainly the zero polynomial
          return true;
        }
        const std::optional<std::vector<FastRoot>> r = isolate_roots_bounded(p, roots);
        if (!r) return false;
        sign = sign_at_start_bounded(p);
        out = fast_span_roots(*r, s, B, kappa_at);
        return true;
      };
      const bool e = fast(eta_b, span.eta_zero, start.eta, span.inflections);
      // eta certainly the zero polynomial (a straight segment): so is
      // lambda = eta' g - (3/2) eta g', whatever bounds its doubles carry.
      bool l = true;
      if (e && span.eta_zero) {
        span.lambda_zero = true;
        start.lambda = 0;
      } else {
        l = fast(lambda_b, span.lambda_zero, start.lambda, span.extrema);
      }
      if (!l) {
        const Bernstein<Rational> lambda = lambda_exact();
        span.lambda_zero = is_zero(lambda);
        start.lambda = sign_at_start(lambda);
        span.extrema = span_roots(lambda, s, kappa_at, roots);
      }
      if (!e) {
        const Bernstein<Rational> eta = eta_exact();
        span.eta_zero = is_zero(eta);
        start.eta = sign_at_start(eta);
        span.inflections = span_roots(eta, s, kappa_at, roots);
      }
      return span;
    }
  }
  const bool fast = fast_paths_enabled();  // off: every sign from the exact polynomials
  start.lambda = fast ? strict_sign(lambda_b) : 0;
  if (start.lambda == 0) {
    const Bernstein<Rational> lambda = lambda_exact();
    span.lambda_zero = is_zero(lambda);
    start.lambda = sign_at_start(lambda);
    span.extrema = span_roots(lambda, s, kappa_at, roots);
  }
  start.eta = fast ? strict_sign(eta_b) : 0;
  if (start.eta == 0) {
    const Bernstein<Rational> eta = eta_exact();
    span.eta_zero = is_zero(eta);
    start.eta = sign_at_start(eta);
    span.inflections = span_roots(eta, s, kappa_at, roots);
  }
  // The curvature's sign is W's times D's (kappa = W^3 D / |h|^3).
  if (spline.is_rational() && weight_sign(spline, s) < 0) {
    start.eta = -start.eta;
    for (SpanRoot& x : span.inflections) x.sign_before = -x.sign_before, x.sign_after = -x.sign_after;
  }
  return span;
}

/// Continuity of every joint: C<k> from the knots; G1/G2 as analyze finds
/// them (joint_between). A closed spline's seam (the end of segment N-1
/// against the start of segment 0) is joint N, judged like the others.
std::vector<JointReport> joint_reports(const SplineAnalysis& analysis) {
  std::vector<Joint> joints = analysis.joints;
  if (analysis.seam) joints.push_back(*analysis.seam);
  std::vector<JointReport> out;
  for (const Joint& j : joints) out.push_back({j, std::string(1, 'C') + std::to_string(j.continuity), !j.g1});
  return out;
}

/// The curvature extrema and inflections of the whole curve. dkappa/ds along
/// the curve: lambda's signs inside the segments and the curvature jumps at
/// joints that are not C2 (a jump is a stretch of zero length in its own
/// direction). Straight segments (lambda == 0) keep the curvature constant
/// and add nothing.
void find_events(SplineReport& r, const std::vector<StartSigns>& start) {
  const BSpline& spline = *r.spline;
  const int N = spline.segment_count();
  // On a closed spline the last segment ends on the seam (joint N), whose
  // jump follows it, and the curve goes on with its first stretch again.
  const int last_joint = spline.closed() ? N : -1;
  auto span_end = [&](int i) { return Place{spline.segments()[i].b, -1, i + 1 < N ? i + 1 : last_joint, 0}; };
  std::vector<Stretch> slope, sign;
  for (int i = 0; i < N; ++i) {
    if (i > 0 && r.joints[i - 1].joint.jump != 0)
      slope.push_back({r.joints[i - 1].joint.jump, {spline.segments()[i].a, -1, i, 0}});
    if (r.spans[i].shape.pole) {  // the curve passes through infinity: no event across it
      slope.push_back({0, span_end(i)});
      sign.push_back({0, span_end(i)});
      continue;
    }
    if (!r.spans[i].lambda_zero) add_span_stretches(slope, start[i].lambda, r.spans[i].extrema, i, span_end(i));
    if (!r.spans[i].eta_zero) add_span_stretches(sign, start[i].eta, r.spans[i].inflections, i, span_end(i));
  }
  if (spline.closed()) {
    if (r.joints[N - 1].joint.jump != 0) slope.push_back({r.joints[N - 1].joint.jump, {spline.domain_end(), -1, N, 0}});
    if (!slope.empty()) slope.push_back(slope.front());
    if (!sign.empty()) sign.push_back(sign.front());
  }
  for (const SignChange& c : sign_changes(slope)) {
    CurveEvent e{c.at.t, c.before > 0 ? 1 : -1, c.at.kappa, c.at.segment, c.at.joint};
    if (c.at.joint >= 0) {
      const Joint& j = r.joints[c.at.joint - 1].joint;
      e.kappa = e.kind > 0 ? std::max(j.kappa_left, j.kappa_right) : std::min(j.kappa_left, j.kappa_right);
    }
    r.extrema.push_back(e);
  }
  for (const SignChange& c : sign_changes(sign))
    r.inflections.push_back({c.at.t, c.after, 0, c.at.segment, c.at.joint});
  r.monotone_pieces = static_cast<int>(r.extrema.size()) + 1;
}

/// Curvature range: its extremes are at segment ends or stationary points
/// (certified values). With a cusp (P' = 0 somewhere) the curvature is
/// unbounded or undefined there, and a pole sends the curve through
/// infinity: no finite range (NaN, null in JSON). In the same pass, each
/// segment's relative spread (SpanReport::kappa_spread) and its
/// turning_deviation from the same values (the extremes of kappa over a
/// segment lie there too), near_constant against `tolerance`.
void curvature_range(SplineReport& r, double tolerance) {
  r.cusp = r.analysis.cusp;
  const bool bounded = !(r.cusp || r.analysis.pole);
  r.kappa_min = bounded ? std::numeric_limits<double>::infinity() : std::numeric_limits<double>::quiet_NaN();
  r.kappa_max = -r.kappa_min;
  if (!bounded) r.kappa_max = r.t_min = r.t_max = r.kappa_min;
  const BSpline& spline = *r.spline;
  for (SpanReport& span : r.spans) {
    if (span.shape.cusp || span.shape.pole) {
      span.kappa_spread = span.turning_deviation = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    auto consider = [&](double t, double k) {
      lo = std::min(lo, k), hi = std::max(hi, k);
      if (!bounded) return;
      if (k < r.kappa_min) r.kappa_min = k, r.t_min = t;
      if (k > r.kappa_max) r.kappa_max = k, r.t_max = t;
    };
    // The end curvatures analyze certified at the joints (the same
    // certified_end_curvature values), computed here only at an open
    // spline's two ends and beside a pole.
    const int i = span.segment.index, N = static_cast<int>(r.spans.size());
    const bool joints = static_cast<int>(r.analysis.joints.size()) == N - 1;
    const Joint* before = i > 0 ? &r.analysis.joints[static_cast<std::size_t>(i - 1)]
                                : (r.analysis.seam ? &*r.analysis.seam : nullptr);
    const Joint* after = i + 1 < N ? &r.analysis.joints[static_cast<std::size_t>(i)]
                                   : (r.analysis.seam ? &*r.analysis.seam : nullptr);
    if (!joints) before = after = nullptr;
    consider(span.segment.a, before && !before->pole ? before->kappa_right : certified_end_curvature(spline, span.segment, 0));
    consider(span.segment.b, after && !after->pole ? after->kappa_left : certified_end_curvature(spline, span.segment, 1));
    for (const SpanRoot& x : span.extrema) consider(x.t, x.kappa);
    const double scale = std::max(std::abs(lo), std::abs(hi));
    span.kappa_spread = scale > 0 ? (hi - lo) / scale : 0;
    span.turning_deviation = turning_deviation(lo, hi, polygon_length(bezier_segment(spline, span.segment).points));
    span.near_constant = span.turning_deviation <= tolerance;
  }
}

}  // namespace

std::string pole_message(const SpanReport& span) {
  std::ostringstream out;
  out.precision(6);
  out << "segment " << span.segment.index << " has a pole at t≈";
  for (std::size_t k = 0; k < span.shape.poles.size(); ++k) out << (k ? ", " : "") << span.shape.poles[k];
  return out.str();
}

SplineReport report_spline(const BSpline& spline, const ReportOptions& options) {
  SplineReport r;
  r.spline = spline;
  r.name = spline.name();
  r.analysis = analyze(spline, analyze_options(options));
  r.requirement_pass = passes(r.analysis, check_of(options));
  ExactPoints exact(spline);
  std::vector<StartSigns> start(spline.segment_count());
  for (int i = 0; i < spline.segment_count(); ++i) {
    r.spans.push_back(span_report(spline, i, r.analysis.segments[i], r.analysis.shapes[i], options.roots, exact, start[i]));
  }
  r.joints = joint_reports(r.analysis);
  find_events(r, start);
  curvature_range(r, options.constant_tolerance);
  // With gates alone the monotonicity check is informational (a closed
  // contour is never monotone over its period). The gates are judged on this
  // report afterwards (report/batch.hpp: judge_gates).
  const bool judged = options.require.has_value() || options.gates.empty();
  r.pass = !judged || r.requirement_pass;
  return r;
}

namespace {

/// Whether pixel `index` may pass the check: increasing or decreasing, or
/// with a split an extremum at the joint (sharpest or flattest depends on the
/// sign of kappa there, which find_fixes decides per pixel).
bool passing_label(const RegionResult& image, std::size_t index, const Requirement&) {
  if (image.split) {
    const Split l = image.split_labels[index];
    return l == Split::inc_dec || l == Split::dec_inc;
  }
  const Direction l = image.labels[index];
  return l == Direction::increasing || l == Direction::decreasing;
}

std::string thumbnail(const BSpline& spline, const RegionResult& image, bool split, int max_depth, Vec2 from, Vec2 to) {
  draw::RegionPicture picture;
  picture.spline = &spline;
  picture.layers = {&image};
  picture.split = split;
  picture.max_depth = max_depth;
  picture.moved = std::make_pair(from, to);
  return draw::region_png(picture);
}

}  // namespace

void find_fixes(SplineReport& report, const ReportOptions& options) {
  const BSpline& spline = *report.spline;
  const Requirement check = check_of(options);
  // The points that act on a judged segment: moving any other one leaves
  // every judged segment, so the verdict, as it is (no region, not drawn).
  const int N = spline.segment_count();
  const int first = options.segments ? std::max(0, options.segments->first) : 0;
  const int last = options.segments ? std::min(N - 1, options.segments->last) : N - 1;
  std::vector<bool> acts(static_cast<std::size_t>(spline.unique_point_count()), false);
  for (int i = first; i <= last; ++i)
    for (int k : segment_points(spline, spline.segments()[i])) acts[static_cast<std::size_t>(k)] = true;
  // split:S:sharpest|flattest: a pixel passes only when the extremum at S
  // is the one asked for, which the signs of kappa on the joint's two sides
  // decide for that position (certified: joint_between, as analyze).
  const bool kind_asked = check.split && check.extremum != Extremum::any;
  const auto asked_kind = [&](int k, Vec2 c, Split label) {
    const BSpline moved = spline.with_point(k, c);
    return split_passes(label, check.extremum, joint_between(moved, *check.split - 1, *check.split, options.continuity));
  };
  std::vector<Fix> fixes;
  for (int k = 0; k < spline.unique_point_count(); ++k) {  // a closed spline's twins move with k
    if (!acts[static_cast<std::size_t>(k)]) {
      Fix none;
      none.point = k;
      fixes.push_back(std::move(none));
      continue;
    }
    RegionRequest ro;
    ro.point = k;
    ro.mode = check.mode;
    ro.split = check.split;
    ro.segments = options.segments;
    ro.max_depth = options.max_depth;
    ro.width = ro.height = options.region_size;
    CMR_CHECK(options.backend != nullptr);
    const RegionResult image = options.backend->render(RegionProblem::make(spline, ro));
    Fix fix;
    fix.point = k;
    const Vec2 current = spline.points()[k];
    std::vector<std::pair<double, Vec2>> candidates;
    for (int j = 0; j < image.height; ++j)
      for (int i = 0; i < image.width; ++i) {
        const std::size_t index = static_cast<std::size_t>(j) * image.width + i;
        if (!passing_label(image, index, check)) continue;
        const Vec2 c = pixel_center(image.view, image.width, image.height, i, j);
        if (kind_asked && !asked_kind(k, c, image.split_labels[index])) continue;
        candidates.emplace_back(dot(c - current, c - current), c);
      }
    std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    fix.pixels = candidates.size();
    // Every candidate has the kind asked for: the nearest is verified by analyze.
    if (!candidates.empty()) {
      fix.example = candidates.front().second;
      fix.verified = passes(analyze(spline.with_point(k, *fix.example), analyze_options(options)), check);
    }
    if (fix.example) {
      fix.thumbnail_png = thumbnail(spline, image, check.split.has_value(), options.max_depth, current, *fix.example);
    }
    fixes.push_back(std::move(fix));
  }
  report.fixes = std::move(fixes);
}

ReportInput read_input(const std::string& file) {
  ReportInput in;
  in.file = file;
  try {
    in.spline = read_spline_file(file);
  } catch (const InputError& e) {
    in.error = marked_text(e);  // fields marked (spline/fields.hpp): shown as the run's options say
  }
  return in;
}

int exit_code(const std::vector<SplineReport>& reports, const ReportOptions& options) {
  bool invalid = false, fail = false;
  for (const SplineReport& r : reports) {
    invalid = invalid || !r.error.empty();
    fail = fail || (r.error.empty() && !r.pass);
  }
  if (invalid) return kExitInvalid;
  if (fail && (options.require || !options.gates.empty())) return kExitFail;
  return kExitPass;
}

// ---------------------------------------------------------------- JSON

nlohmann::ordered_json gates_json(const SplineReport& r) {
  nlohmann::ordered_json gates = nlohmann::ordered_json::array();
  for (const GateResult& g : r.gates) {
    nlohmann::ordered_json where = nlohmann::ordered_json::array();
    for (const GateViolation& v : g.violations) {
      nlohmann::ordered_json w{{"t", v.t}, {"message", v.message}};
      if (v.segment >= 0) w["segment"] = v.segment, w["local_t"] = v.local_t;
      if (v.joint >= 0) w["joint"] = v.joint;
      where.push_back(w);
    }
    gates.push_back({{"gate", to_string(g.gate)}, {"pass", g.pass()}, {"violations", where}});
  }
  return gates;
}

const char* status_word(const SplineReport& r) { return !r.error.empty() ? "invalid" : (r.pass ? "pass" : "fail"); }

const char* root_kind_word(int sign_before, int sign_after) {
  if (sign_before == sign_after) return "touch";
  return sign_before > 0 ? "maximum" : "minimum";  // lambda + to -: kappa rises, then falls
}

const char* root_at_word(SpanRoot::At at) {
  switch (at) {
    case SpanRoot::At::interior: return "interior";
    case SpanRoot::At::start: return "start";
    case SpanRoot::At::end: return "end";
  }
  return "?";
}

namespace {

using Json = nlohmann::ordered_json;

Json root_json(const SpanRoot& r, bool extremum) {
  Json j{{"t", r.t}, {"enclosure", {r.t_lo, r.t_hi}}, {"exact", r.exact}, {"multiplicity", r.multiplicity}};
  if (extremum) {
    j["kind"] = root_kind_word(r.sign_before, r.sign_after);
    j["kappa"] = r.kappa;
  } else {
    j["kind"] = r.sign_before == r.sign_after ? "touch" : "sign change";
  }
  j["at"] = root_at_word(r.at);
  return j;
}

Json place_json(Json j, const CurveEvent& e) {
  j["on_joint"] = e.joint >= 0;
  j["segment"] = e.segment >= 0 ? Json(e.segment) : Json(nullptr);
  j["joint"] = e.joint >= 0 ? Json(e.joint) : Json(nullptr);
  return j;
}

Json segments_json(const SplineReport& r) {
  Json segments = Json::array();
  for (const SpanReport& sp : r.spans) {
    Json e = Json::array(), i = Json::array();
    for (const SpanRoot& x : sp.extrema) e.push_back(root_json(x, true));
    for (const SpanRoot& x : sp.inflections) i.push_back(root_json(x, false));
    if (!r.analysis.judged(sp.segment.index)) {  // --segments: not judged, its roots still listed
      segments.push_back({{"index", sp.segment.index},
                          {"interval", {sp.segment.a, sp.segment.b}},
                          {"ignored", true},
                          {"curvature", "ignored"},
                          {"inflection", "ignored"},
                          {"lambda_zero", sp.lambda_zero},
                          {"eta_zero", sp.eta_zero},
                          {"extrema", e},
                          {"inflections", i}});
      continue;
    }
    segments.push_back({{"index", sp.segment.index},
                        {"interval", {sp.segment.a, sp.segment.b}},
                        {"class", shape_class(sp.shape)},
                        {"curvature", to_string(sp.classification.monotonicity.curvature)},
                        {"inflection", to_string(sp.shape.inflection)},
                        {"zero_curvature_at", kappa_zero_at(sp.shape)},
                        {"algorithm2", to_string(sp.classification.inflection.inflection)},
                        {"depth", sp.classification.monotonicity.depth},
                        {"inflection_depth", sp.classification.inflection.depth},
                        {"exact", sp.classification.exact_used},
                        {"lambda_zero", sp.lambda_zero},
                        {"eta_zero", sp.eta_zero},
                        {"kappa_spread", std::isfinite(sp.kappa_spread) ? Json(sp.kappa_spread) : Json(nullptr)},
                        {"turning_deviation", std::isfinite(sp.turning_deviation) ? Json(sp.turning_deviation) : Json(nullptr)},
                        {"near_constant", sp.near_constant},
                        {"extrema", e},
                        {"inflections", i}});
    if (sp.shape.pole) segments.back()["poles"] = sp.shape.poles;
  }
  return segments;
}

Json joints_json(const SplineReport& r) {
  Json joints = Json::array();
  for (const JointReport& jr : r.joints) {
    joints.push_back(joint_json(jr.joint, {jr.corner, false, false}));
  }
  return joints;
}

/// The fixes, or null when none were searched (a passing spline, or regions off).
Json fixes_json(const SplineReport& r) {
  if (!r.fixes) return nullptr;
  Json fixes = Json::array();
  for (const Fix& f : *r.fixes) {
    Json fj{{"point", f.point}, {"region_pixels", f.pixels}};
    fj["example"] = f.example ? Json{f.example->x, f.example->y} : Json(nullptr);
    fj["verified"] = f.verified;
    fixes.push_back(fj);
  }
  return fixes;
}

}  // namespace

bool straight_only(const SplineReport& r) {
  if (!r.error.empty() || r.spans.empty()) return false;
  const int last = std::min(r.analysis.range.last, static_cast<int>(r.spans.size()) - 1);
  for (int i = std::max(0, r.analysis.range.first); i <= last; ++i)
    if (!r.spans[static_cast<std::size_t>(i)].eta_zero) return false;
  return true;
}

std::string verdict_label(const SplineReport& r, Direction d) { return straight_only(r) ? "straight" : to_string(d); }

namespace {

Json spline_json(const SplineReport& r, int index) {
  Json j{{"id", "s" + std::to_string(index)}, {"file", r.file}, {"name", r.name}, {"status", status_word(r)}};
  if (!r.error.empty()) {
    j["error"] = r.error;
    return j;
  }
  const BSpline& s = *r.spline;
  j["degree"] = s.degree();
  j["control_points"] = s.unique_point_count();  // a closed spline's distinct points
  j["domain"] = {s.domain_begin(), s.domain_end()};
  Json verdict{{"cmrwi", verdict_label(r, r.analysis.cmrwi)},
               {"cmr", verdict_label(r, r.analysis.cmr)},
               {"cmr_algorithm2", to_string(r.analysis.cmr_algorithm2)}};
  if (r.analysis.split) verdict["split"] = to_string(*r.analysis.split);
  if (r.analysis.range != SegmentRange{0, s.segment_count() - 1})
    verdict["segments"] = {r.analysis.range.first, r.analysis.range.last};
  verdict["joint_conflicts"] = r.analysis.joint_conflicts;
  j["verdict"] = verdict;

  Json extrema = Json::array(), inflections = Json::array();
  for (const CurveEvent& e : r.extrema)
    extrema.push_back(place_json({{"t", e.t},
                                  {"kind", to_string(event_kind(r, e))},              // by |kappa|
                                  {"direction", e.kind > 0 ? "maximum" : "minimum"},  // of signed kappa
                                  {"kappa", e.kappa}},
                                 e));
  for (const CurveEvent& e : r.inflections)
    inflections.push_back(place_json({{"t", e.t}, {"kappa_sign_after", e.kind}}, e));
  // With a cusp there is no finite range: NaN prints as null.
  j["curvature"] = {{"cusp", r.cusp},
                    {"min", {{"kappa", r.kappa_min}, {"t", r.t_min}}},
                    {"max", {{"kappa", r.kappa_max}, {"t", r.t_max}}},
                    {"monotone_pieces", r.monotone_pieces},
                    {"extrema", extrema},
                    {"inflections", inflections}};
  if (r.analysis.pole) j["curvature"]["pole"] = true;  // no finite range either (null)

  j["segments"] = segments_json(r);
  j["joints"] = joints_json(r);
  j["fixes"] = fixes_json(r);
  if (!r.certified_fixes.empty()) {
    j["certified_fixes"] = Json::array();
    for (const CertifiedFix& f : r.certified_fixes) j["certified_fixes"].push_back(certified_fix_json(f));
  }
  if (s.closed()) j["closed"] = true;
  if (!r.gates.empty()) j["gates"] = gates_json(r);
  return j;
}

}  // namespace

nlohmann::ordered_json report_json(const std::vector<SplineReport>& reports, const ReportOptions& options) {
  int pass = 0, fail = 0, invalid = 0;
  Json splines = Json::array();
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const SplineReport& r = reports[i];
    (!r.error.empty() ? invalid : (r.pass ? pass : fail))++;
    splines.push_back(spline_json(r, static_cast<int>(i)));
  }
  Json regions = nullptr;
  if (options.regions)
    regions = {{"size", options.region_size},
               {"backend", options.backend ? options.backend->name() : "none"}};
  return {{"schema", kSchema},
          {"settings",
           {{"check", to_string(check_of(options))},
            {"gate", options.require.has_value() || !options.gates.empty()},
            {"segments", options.segments ? Json{options.segments->first, options.segments->last} : Json(nullptr)},
            {"type_gates", [&] {
               Json g = Json::array();
               for (const Gate& x : options.gates) g.push_back(to_string(x));
               return g;
             }()},
            {"depth", options.max_depth},
            {"root_tolerance", options.roots.tolerance},
            {"constant_tolerance", options.constant_tolerance},
            {"regions", regions}}},
          {"summary",
           {{"splines", reports.size()},
            {"pass", pass},
            {"fail", fail},
            {"invalid", invalid},
            {"exit_code", exit_code(reports, options)}}},
          {"splines", splines}};
}

// ---------------------------------------------------------------- HTML

namespace {

// Colours shared by the pictures and the page. Extrema by their |kappa|
// reading, the words of the messages and the gates (report/extremum.hpp):
// sharpest red, flattest blue, an extremum at an inflection purple; a signed
// maximum where kappa < 0 is a flattest point, so the signed words would
// contradict the messages.
constexpr const char* kRed = "#d00000";
constexpr const char* kBlue = "#0040d0";
constexpr const char* kGreen = "#108010";
constexpr const char* kPurple = "#8000a0";

const char* extremum_colour(const SplineReport& r, const CurveEvent& e) {
  switch (event_kind(r, e)) {
    case ExtremumKind::sharpest: return kRed;
    case ExtremumKind::flattest: return kBlue;
    case ExtremumKind::inflection: return kPurple;
  }
  return kPurple;
}

void fixed(std::string& out, double v, int decimals = 1) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  out.append(buf, r.ptr);
}

std::string num(double v) {
  if (!std::isfinite(v)) return std::isnan(v) ? "undefined" : (v > 0 ? "∞" : "−∞");
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6);
  return std::string(buf, r.ptr);
}

// Maps world coordinates into an SVG box with a 10 px margin, y up; `left`
// and `bottom` centre content that does not fill the box.
struct Canvas {
  double x0, y0, scale_x, scale_y, height;
  double left = 10, bottom = 10;
  double x(double wx) const { return (wx - x0) * scale_x + left; }
  double y(double wy) const { return height - bottom - (wy - y0) * scale_y; }
};

void point_xy(std::string& out, const Canvas& c, Vec2 p) {
  fixed(out, c.x(p.x));
  out += ',';
  fixed(out, c.y(p.y));
}

void marker(std::string& out, double x, double y, const char* colour, double radius = 4) {
  out += "<circle cx=\"";
  fixed(out, x);
  out += "\" cy=\"";
  fixed(out, y);
  out += "\" r=\"";
  fixed(out, radius);
  out += "\" fill=\"";
  out += colour;
  out += "\"/>";
}

constexpr int kSamples = 24;  // per segment, for the curve, the comb and the plot

/// The curve picture's canvas and its curvature comb: teeth along the
/// normal, away from the centre of curvature, the longest 18% of the extent.
struct CombCanvas {
  Canvas canvas{0, 0, 1, 1, 0};
  double comb = 0;  ///< tooth length per unit of curvature
  Vec2 tip(const Frame& f) const {
    const double len = std::sqrt(dot(f.tangent, f.tangent));
    const Vec2 normal = len > 0 ? Vec2(-f.tangent.y, f.tangent.x) / len : Vec2(0.0);
    return f.point - comb * (std::isfinite(f.kappa) ? f.kappa : 0.0) * normal;
  }
};

/// A canvas of W x H on which the control points, the curve and the comb all fit.
CombCanvas comb_canvas(const BSpline& s, const std::vector<std::vector<Frame>>& frames, double W, double H) {
  Vec2 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  double kmax = 0;
  auto grow = [&](Vec2 p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return;
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  };
  for (const Vec2& p : s.points()) grow(p);
  for (const auto& fs : frames)
    for (const Frame& f : fs) {
      if (!f.drawn) continue;
      grow(f.point);
      if (std::isfinite(f.kappa)) kmax = std::max(kmax, std::fabs(f.kappa));
    }
  CombCanvas cc;
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, 1e-300});
  cc.comb = kmax > 0 ? 0.18 * extent / kmax : 0;
  for (const auto& fs : frames)
    for (const Frame& f : fs)
      if (f.drawn) grow(cc.tip(f));
  const double scale = std::min((W - 20) / std::max(hi.x - lo.x, 1e-300), (H - 20) / std::max(hi.y - lo.y, 1e-300));
  cc.canvas = {lo.x, lo.y, scale, scale, H, 0.5 * (W - (hi.x - lo.x) * scale), 0.5 * (H - (hi.y - lo.y) * scale)};
  return cc;
}

/// An SVG path of one polyline per segment through point(frame), broken
/// where frames are not drawn and where W changes sign (across a pole).
template <class PointOf>
void polylines(std::string& out, const Canvas& c, const std::vector<std::vector<Frame>>& frames, PointOf point) {
  for (const auto& fs : frames) {
    const Frame* last = nullptr;  // the previous frame, while the line goes on
    for (const Frame& f : fs) {
      if (!f.drawn) {
        last = nullptr;
        continue;
      }
      if (!last || (last->weight > 0) != (f.weight > 0)) out += 'M';
      point_xy(out, c, point(f));
      out += ' ';
      last = &f;
    }
  }
}

/// Control point names, and markers at the extrema and inflections.
void curve_marks_svg(std::string& out, const SplineReport& r, const Canvas& c) {
  const BSpline& s = *r.spline;
  for (int k = 0; k < s.point_count(); ++k) {
    const Vec2 p = s.points()[k];
    marker(out, c.x(p.x), c.y(p.y), "#666", 2.5);
    out += "<text font-size=\"10\" fill=\"#444\" x=\"";
    fixed(out, c.x(p.x) + 4);
    out += "\" y=\"";
    fixed(out, c.y(p.y) - 4);
    out += "\">P" + std::to_string(k) + "</text>";
  }
  const CurveSampler sampler(s);
  for (const CurveEvent& e : r.extrema) {
    const Vec2 p = evaluate(s, e.t);
    if (sampler.inside(p)) marker(out, c.x(p.x), c.y(p.y), extremum_colour(r, e), 4.5);
  }
  for (const CurveEvent& e : r.inflections) {
    const Vec2 p = evaluate(s, e.t);
    if (sampler.inside(p)) marker(out, c.x(p.x), c.y(p.y), kGreen, 3.5);
  }
}

/// The curve, its control polygon and its curvature comb.
void curve_svg(std::string& out, const SplineReport& r, const std::vector<std::vector<Frame>>& frames) {
  const CombCanvas cc = comb_canvas(*r.spline, frames, 440, 330);
  const Canvas& c = cc.canvas;
  out += draw::svg_open({{"width", "440"}, {"height", "330"}, {"class", "curve"}});
  out += "<path fill=\"none\" stroke=\"#8fb0e8\" stroke-width=\"1\" d=\"";
  for (const auto& fs : frames)
    for (const Frame& f : fs) {
      if (!f.drawn) continue;
      out += 'M';
      point_xy(out, c, f.point);
      out += 'L';
      point_xy(out, c, cc.tip(f));
    }
  out += "\"/><path fill=\"none\" stroke=\"";
  out += kBlue;
  out += "\" stroke-width=\"1.2\" d=\"";
  polylines(out, c, frames, [&](const Frame& f) { return cc.tip(f); });
  out += "\"/><polyline fill=\"none\" stroke=\"#999\" stroke-dasharray=\"4 3\" points=\"";
  for (const Vec2& p : r.spline->points()) {
    point_xy(out, c, p);
    out += ' ';
  }
  out += "\"/><path fill=\"none\" stroke=\"#111\" stroke-width=\"2\" d=\"";
  polylines(out, c, frames, [](const Frame& f) { return f.point; });
  out += "\"/>";
  curve_marks_svg(out, r, c);
  out += draw::kSvgClose;
}

// Signed curvature against the parameter: knots dashed, extrema as on the
// curve (sharpest red, flattest blue), inflections green.
void plot_svg(std::string& out, const SplineReport& r, const std::vector<std::vector<Frame>>& frames) {
  const BSpline& s = *r.spline;
  const double W = 440, H = 240;
  double klo = std::isfinite(r.kappa_min) ? std::min(r.kappa_min, 0.0) : 0.0;
  double khi = std::isfinite(r.kappa_max) ? std::max(r.kappa_max, 0.0) : 0.0;
  if (!(khi > klo)) khi = klo + 1;
  const double pad = 0.06 * (khi - klo);
  klo -= pad;
  khi += pad;
  const double t0 = s.domain_begin(), t1 = s.domain_end();
  const Canvas c{t0, klo, (W - 20) / (t1 - t0), (H - 20) / (khi - klo), H};
  out += draw::svg_open({{"width", "440"}, {"height", "240"}, {"class", "plot"}});
  out += "<rect x=\"10\" y=\"10\" width=\"420\" height=\"220\" fill=\"#fafafa\" stroke=\"#ccc\"/>";
  out += "<line stroke=\"#aaa\" x1=\"10\" x2=\"430\" y1=\"";
  fixed(out, c.y(0));
  out += "\" y2=\"";
  fixed(out, c.y(0));
  out += "\"/><path stroke=\"#bbb\" stroke-dasharray=\"3 3\" d=\"";
  for (const Segment& seg : s.segments()) {
    out += 'M';
    fixed(out, c.x(seg.a));
    out += ",10V230";
  }
  out += "\"/><path fill=\"none\" stroke=\"#111\" stroke-width=\"1.5\" d=\"";
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const Segment& seg = s.segments()[i];
    bool pen = false;
    for (int k = 0; k <= kSamples; ++k) {
      if (!frames[i][k].drawn) {  // near a pole
        pen = false;
        continue;
      }
      if (!pen) out += 'M';
      pen = true;
      const double kappa = std::clamp(frames[i][k].kappa, klo, khi);  // a cusp's infinity stays on the plot
      fixed(out, c.x(seg.a + (seg.b - seg.a) * k / kSamples));
      out += ',';
      fixed(out, c.y(std::isnan(kappa) ? 0.0 : kappa));
      out += ' ';
    }
  }
  out += "\"/>";
  for (const CurveEvent& e : r.extrema)
    marker(out, c.x(e.t), c.y(std::clamp(e.kappa, klo, khi)), extremum_colour(r, e), 4.5);
  for (const CurveEvent& e : r.inflections) marker(out, c.x(e.t), c.y(0), kGreen, 3.5);
  out += "<text font-size=\"10\" x=\"14\" y=\"22\">κ " + html_escape(num(khi)) + "</text>";
  out += "<text font-size=\"10\" x=\"14\" y=\"226\">κ " + html_escape(num(klo)) + "</text>";
  out += "<text font-size=\"10\" x=\"380\" y=\"226\">t " + html_escape(num(t1)) + "</text>";
  out += draw::kSvgClose;
}

std::string badge(const SplineReport& r) {
  const std::string st = status_word(r);
  std::string label = st;
  std::transform(label.begin(), label.end(), label.begin(), [](unsigned char ch) { return std::toupper(ch); });
  return "<span class=\"badge " + st + "\">" + label + "</span>";
}

std::string roots_cell(const std::vector<SpanRoot>& roots, bool extremum) {
  std::string out;
  for (const SpanRoot& x : roots) {
    if (!out.empty()) out += "<br>";
    const std::string kind = extremum ? root_kind_word(x.sign_before, x.sign_after)
                                      : (x.sign_before != x.sign_after ? "sign change" : "touch");
    out += num(x.t) + (x.exact ? " (exact) " : " ") + kind;
    if (x.multiplicity > 1) out += " ×" + std::to_string(x.multiplicity);
  }
  return out.empty() ? "—" : out;
}

std::string place_text(const CurveEvent& e) {
  return e.joint >= 0 ? "on joint " + std::to_string(e.joint) : "inside segment " + std::to_string(e.segment);
}

/// The verdicts, the size of the spline and its curvature range in one paragraph.
void summary_html(std::string& out, const SplineReport& r, const ReportOptions& options) {
  const BSpline& s = *r.spline;
  out += "<p>check <b>" + html_escape(to_string(check_of(options))) + "</b>: CMRWI " + verdict_label(r, r.analysis.cmrwi) +
         ", CMR " + verdict_label(r, r.analysis.cmr);
  if (r.analysis.split) out += ", split " + std::string(to_string(*r.analysis.split));
  if (r.analysis.range != SegmentRange{0, s.segment_count() - 1})
    out += " (segments " + std::to_string(r.analysis.range.first) + ".." + std::to_string(r.analysis.range.last) +
           " judged, the others ignored)";
  out += ". Degree " + std::to_string(s.degree()) + ", " + std::to_string(s.segment_count()) +
         (s.segment_count() == 1 ? " segment, " : " segments, ") + std::to_string(r.monotone_pieces) +
         " monotone curvature piece" + (r.monotone_pieces == 1 ? "" : "s") +
         (r.cusp ? "; a cusp (zero tangent): κ is unbounded, no finite range.</p>"
                 : "; κ from " + num(r.kappa_min) + " (t = " + num(r.t_min) + ") to " + num(r.kappa_max) +
                       " (t = " + num(r.t_max) + ").</p>");
}

/// One row per segment: its class, decision depths and roots.
void spans_html(std::string& out, const SplineReport& r) {
  out +=
      "<table><tr><th>segment</th><th>interval</th><th>curvature</th><th>inflection</th><th>depth</th>"
      "<th>stationary points of κ</th><th>zeros of κ</th></tr>";
  for (const SpanReport& sp : r.spans) {
    const bool judged = r.analysis.judged(sp.segment.index);
    if (sp.shape.pole) {  // the curve passes through infinity
      out += "<tr><td>" + std::to_string(sp.segment.index) + "</td><td>[" + num(sp.segment.a) + ", " +
             num(sp.segment.b) + "]</td><td colspan=\"5\" class=\"error\">" + html_escape(pole_message(sp)) +
             "</td></tr>";
      continue;
    }
    out += "<tr><td>" + std::to_string(sp.segment.index) + "</td><td>[" + num(sp.segment.a) + ", " + num(sp.segment.b) +
           "]</td><td>" + (judged ? to_string(sp.classification.monotonicity.curvature) : "ignored") + "</td><td>" +
           (judged ? to_string(sp.classification.inflection.inflection) : "ignored") + "</td><td>" +
           (judged ? std::to_string(sp.classification.monotonicity.depth) + " / " +
                         std::to_string(sp.classification.inflection.depth)
                   : "—") +
           "</td><td>" + roots_cell(sp.extrema, true) +
           (sp.near_constant && !sp.lambda_zero ? " (κ constant: turning within " + num(sp.turning_deviation) + " rad)" : "") +
           "</td><td>" + roots_cell(sp.inflections, false) + "</td></tr>";
  }
  out += "</table>";
}

/// One row per joint (none for a single segment).
void joints_html(std::string& out, const SplineReport& r) {
  if (!r.joints.empty()) {
    out +=
        "<table><tr><th>joint</th><th>knot</th><th>multiplicity</th><th>continuity</th><th>G1</th><th>G2</th>"
        "<th>κ left</th><th>κ right</th><th>jump</th></tr>";
    for (const JointReport& j : r.joints)
      out += "<tr><td>" + std::to_string(j.joint.index) + "</td><td>" + num(j.joint.knot) + "</td><td>" +
             std::to_string(j.joint.multiplicity) + "</td><td>" + j.continuity + (j.corner ? " (corner)" : "") +
             "</td><td>" + (j.joint.zero_tangent ? "no (zero tangent)" : (j.joint.g1 ? "yes" : "no")) +
             "</td><td>" + (j.joint.g2 ? "yes" : "no") + "</td><td>" + num(j.joint.kappa_left) + "</td><td>" +
             num(j.joint.kappa_right) + "</td><td>" +
             jump_name(shown_jump(j.joint)) + "</td></tr>";
    out += "</table>";
  }
}

/// The extrema and inflections of the whole curve, in parameter order.
void events_html(std::string& out, const SplineReport& r) {
  out += "<p>Curvature extrema: ";
  if (r.extrema.empty()) out += "none";
  for (std::size_t i = 0; i < r.extrema.size(); ++i) {
    const CurveEvent& e = r.extrema[i];
    out += (i ? "; " : "") +
           std::string(event_kind(r, e) == ExtremumKind::sharpest   ? "<span class=\"max\">sharpest</span>"
                       : event_kind(r, e) == ExtremumKind::flattest ? "<span class=\"min\">flattest</span>"
                                                                    : "<span class=\"min\">inflection</span>") +
           " κ = " + num(e.kappa) + " at t = " + num(e.t) + " (" + place_text(e) + ")";
  }
  out += ". Inflections: ";
  if (r.inflections.empty()) out += "none";
  for (std::size_t i = 0; i < r.inflections.size(); ++i)
    out += (i ? "; " : "") + std::string("t = ") + num(r.inflections[i].t) + " (" + place_text(r.inflections[i]) + ")";
  out += ".</p>";
}

/// Single control points that can fix a failing spline, with their thumbnails.
void fixes_html(std::string& out, const std::vector<Fix>& fixes, const ReportOptions& options) {
  out += "<div class=\"fixes\"><h3>Single control points that can fix it</h3>";
  bool any = false;
  for (const Fix& f : fixes) {
    if (!f.example) continue;
    any = true;
    out += "<figure>";
    if (!f.thumbnail_png.empty())
      out += "<img alt=\"region of P" + std::to_string(f.point) + "\" width=\"" +
             std::to_string(options.region_size * 2) + "\" src=\"data:image/png;base64," + base64(f.thumbnail_png) +
             "\">";
    out += "<figcaption>move P" + std::to_string(f.point) + " into its region, e.g. to (" + num(f.example->x) + ", " +
           num(f.example->y) + ")" + (f.verified ? " ✓" : " (not confirmed by analyze)") + "</figcaption></figure>";
  }
  if (!any) out += "<p>No single control point has a region in the default view.</p>";
  out += "</div>";
}

void section_html(std::string& out, const SplineReport& r, int index, const ReportOptions& options) {
  out += "<section id=\"s" + std::to_string(index) + "\"><h2>" + html_escape(r.name) + " " + badge(r) + "</h2>";
  out += "<p class=\"file\">" + html_escape(r.file) + "</p>";
  if (!r.error.empty()) {
    out += "<p class=\"error\">" + html_escape(r.error) + "</p></section>";
    return;
  }
  std::vector<std::vector<Frame>> frames(r.spans.size());
  for (std::size_t i = 0; i < r.spans.size(); ++i)
    for (int k = 0; k <= kSamples; ++k)
      frames[i].push_back(frame_at(r.spans[i].bezier, r.spans[i].homogeneous, static_cast<double>(k) / kSamples));
  // Near a pole the curve runs off to infinity: those frames are not drawn.
  const CurveSampler sampler(*r.spline);
  for (auto& fs : frames)
    for (Frame& f : fs) f.drawn = sampler.inside(f.point) && std::isfinite(f.tangent.x) && std::isfinite(f.tangent.y);
  summary_html(out, r, options);
  out += "<div class=\"figs\"><figure>";
  curve_svg(out, r, frames);
  out +=
      "<figcaption>Curve, control polygon and curvature comb; sharpest points (largest |κ|) red, flattest "
      "(smallest |κ|) blue, extrema at an inflection purple, inflections green</figcaption></figure><figure>";
  plot_svg(out, r, frames);
  out += "<figcaption>Signed curvature κ(t); knots dashed; extrema coloured as on the curve (by |κ|: a sharpest "
         "point where κ &lt; 0 is a minimum of this plot)</figcaption></figure></div>";

  spans_html(out, r);
  joints_html(out, r);
  events_html(out, r);
  if (r.fixes) fixes_html(out, *r.fixes, options);
  for (const CertifiedFix& f : r.certified_fixes) out += certified_fix_html(f, *r.spline);
  out += "</section>";
}

constexpr const char* kStyle =
    "body{font:14px/1.4 sans-serif;margin:24px;color:#222}"
    "table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid #ccc;padding:2px 8px;text-align:left;"
    "vertical-align:top}th{background:#f0f0f0}"
    ".badge{color:#fff;padding:1px 8px;border-radius:3px;font-size:13px}"
    ".pass{background:#1a7f1a}.fail{background:#d00000}.invalid{background:#666}"
    ".max{color:#d00000}.min{color:#0040d0}.error{color:#a00000;font-family:monospace}"
    ".file{color:#666;font-family:monospace;margin:0}"
    ".figs,.fixes{display:flex;flex-wrap:wrap;gap:12px}.fixes h3{width:100%;margin:4px 0}"
    "figure{margin:0}figcaption{font-size:12px;color:#555;max-width:260px}img{border:1px solid #ccc}"
    "section{border-top:2px solid #ddd;margin-top:24px}";

}  // namespace

std::string report_style() { return kStyle; }

std::string report_sections_html(const std::vector<SplineReport>& reports, int first, const ReportOptions& options) {
  std::string out;
  for (std::size_t i = 0; i < reports.size(); ++i) section_html(out, reports[i], first + static_cast<int>(i), options);
  return out;
}

std::string report_html(const std::vector<SplineReport>& reports, const ReportOptions& options) {
  int pass = 0, fail = 0, invalid = 0;
  for (const SplineReport& r : reports) (!r.error.empty() ? invalid : (r.pass ? pass : fail))++;
  const std::string counts = std::to_string(reports.size()) + (reports.size() == 1 ? " spline: " : " splines: ") +
                             std::to_string(pass) + " pass, " + std::to_string(fail) + " fail, " +
                             std::to_string(invalid) + " invalid";
  std::string out;
  out.reserve(reports.size() * 24000);
  out += "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>cmr report — " + counts +
         "</title><style>";
  out += kStyle;
  out += "</style></head><body><h1>cmr report</h1><p>" + counts + "; check <b>" + html_escape(to_string(check_of(options))) +
         "</b>" + (options.require ? " (required)" : " (not required)") + ", depth " +
         std::to_string(options.max_depth) + ", schema " + kSchema + ".</p>";
  out +=
      "<table class=\"index\"><tr><th>#</th><th>spline</th><th>file</th><th>status</th><th>CMRWI</th><th>CMR</th>"
      "<th>monotone pieces</th></tr>";
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const SplineReport& r = reports[i];
    const std::string id = "s" + std::to_string(i);
    out += "<tr><td>" + std::to_string(i) + "</td><td><a href=\"#" + id + "\">" + html_escape(r.name) + "</a></td><td>" +
           html_escape(r.file) + "</td><td>" + badge(r) + "</td>";
    if (r.error.empty())
      out += "<td>" + verdict_label(r, r.analysis.cmrwi) + "</td><td>" + verdict_label(r, r.analysis.cmr) + "</td><td>" +
             std::to_string(r.monotone_pieces) + "</td></tr>";
    else
      out += "<td colspan=\"3\">invalid input</td></tr>";
  }
  out += "</table>";
  for (std::size_t i = 0; i < reports.size(); ++i) section_html(out, reports[i], static_cast<int>(i), options);
  out += "</body></html>\n";
  return out;
}

}  // namespace cmr::report
