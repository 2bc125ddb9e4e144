#include "report/report.hpp"
#include "report/report_detail.hpp"

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

// The report model (report.hpp): requirements, the certified curvature
// events of each span, joints, the curvature range, fixes and the exit code.
// Its JSON is in report_json.cpp, its HTML page in report_html.cpp.

namespace cmr::report {

using namespace report_detail;  // what the parts share (report_detail.hpp)

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

}  // namespace

namespace report_detail {

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

}  // namespace report_detail

namespace {

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
/// arithmetic, and only the others are formed exactly. Without
/// `inflections`, eta is left out (no inflections, eta_zero false, start
/// sign 0): the extrema alone.
SpanReport span_report(const BSpline& spline, int i, const SegmentClass& c, const SegmentShape& shape,
                       const RootOptions& roots, ExactPoints& exact, StartSigns& start, bool inflections = true) {
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
    if (inflections) eta_b = to_bounded(eta_bernstein<Tracked>(B));
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
      // Without inflections (segment_extrema_count) eta is not looked at:
      // lambda alone gives the extrema (a straight segment's lambda is 0).
      const bool e = !inflections || fast(eta_b, span.eta_zero, start.eta, span.inflections);
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
  start.eta = fast && inflections ? strict_sign(eta_b) : 0;
  if (start.eta == 0 && inflections) {
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
  for (const Joint& j : joints) {
    std::string continuity = "C";  // appended: GCC 12 reports a false -Wrestrict on "C" + to_string here
    continuity += std::to_string(j.continuity);
    out.push_back({j, std::move(continuity), !j.g1});
  }
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

std::optional<int> segment_extrema_count(const BSpline& spline, const ReportOptions& options) {
  if (spline.is_rational() || spline.closed() || spline.segment_count() != 1) return std::nullopt;
  // report_spline's parts that curvature-extrema-at-nodes reads on one
  // segment: its extrema (span_report's lambda, find_events) and, when it has
  // any, whether its curvature is near constant (curvature_range, which reads
  // the segment's shape: a cusp has no curvature range). Algorithm 1 and 2,
  // the joints (there are none) and eta are not needed. A polynomial segment
  // has no pole, so the shape is needed for its cusp alone.
  //
  // Where lambda changes sign does not depend on how narrowly its roots are
  // enclosed, so they are first isolated alone (enclosure width 1), and
  // refined to options.roots only where the extrema's curvatures can matter:
  // the segment is near constant only when its curvature range, which
  // contains the two end curvatures, is within the tolerance
  // (turning_deviation grows with the range).
  const Segment& seg = spline.segments()[0];
  SplineReport r;
  r.spline = spline;
  ExactPoints exact(spline);
  std::vector<StartSigns> start(1);
  RootOptions isolated = options.roots;
  isolated.tolerance = 1;
  r.spans.push_back(span_report(spline, 0, SegmentClass{}, SegmentShape{}, isolated, exact, start[0], false));
  find_events(r, start);
  if (r.extrema.empty()) return 0;
  const double k0 = certified_end_curvature(spline, seg, 0), k1 = certified_end_curvature(spline, seg, 1);
  const double ends = turning_deviation(std::min(k0, k1), std::max(k0, k1), polygon_length(bezier_segment(spline, seg).points));
  const auto inside = [&r] {
    return static_cast<int>(std::count_if(r.extrema.begin(), r.extrema.end(), [&](const CurveEvent& e) {
      return e.segment >= 0 && !r.spans[static_cast<std::size_t>(e.segment)].near_constant;
    }));
  };
  if (ends > options.constant_tolerance) return inside();  // near_constant is false
  r.spans.clear();
  r.extrema.clear();
  r.inflections.clear();
  r.spans.push_back(span_report(spline, 0, SegmentClass{}, SegmentShape{}, options.roots, exact, start[0], false));
  find_events(r, start);
  r.analysis.shapes = {segment_shape(spline, seg)};
  r.analysis.cusp = r.analysis.shapes[0].cusp;
  r.spans[0].shape = r.analysis.shapes[0];
  curvature_range(r, options.constant_tolerance);
  return inside();
}

SplineReport report_spline(const BSpline& spline, const ReportOptions& options, bool classify) {
  SplineReport r;
  r.spline = spline;
  r.name = spline.name();
  AnalyzeParts parts = default_analyze_parts();
  if (!classify) parts.classify = [](const BSpline&, const Segment&, const ClassifyOptions&) { return SegmentClass{}; };
  r.analysis = analyze(spline, analyze_options(options), parts);
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

}  // namespace cmr::report
