#include "bezierize/analyze.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "bezierize/decide.hpp"
#include "numeric/double_word.hpp"
#include "bezierize/lambda.hpp"
#include "bezierize/rational_lambda.hpp"
#include "numeric/roots.hpp"
#include "numeric/exact.hpp"
#include "bezierize/extract.hpp"
#include "numeric/fast_path.hpp"
#include "numeric/tracked.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/limits.hpp"
#include "spline/parallel.hpp"

namespace cmr {

const char* to_string(Direction d) {
  switch (d) {
    case Direction::increasing: return "increasing";
    case Direction::decreasing: return "decreasing";
    case Direction::none: return "none";
    case Direction::undecided: return "undecided";
  }
  return "?";
}

const char* to_string(Split s) {
  switch (s) {
    case Split::inc_inc: return "inc-inc";
    case Split::inc_dec: return "inc-dec";
    case Split::dec_inc: return "dec-inc";
    case Split::dec_dec: return "dec-dec";
    case Split::none: return "none";
    case Split::undecided: return "undecided";
  }
  return "?";
}

namespace {

// The first three Bezier points of window w's span from its end e (o the
// other end): f(e^d), f(e^{d-1} o), f(e^{d-2} o^2), from one de Boor
// triangle whose levels with e are shared (10 affine steps for a cubic
// instead of 18, one division each). The same points as blossom_span's up
// to rounding; used for DoubleWord, whose bounds cover any order of
// operations (Tracked keeps blossom_span: its values are printed). d >= 2.
template <class T>
void end_bezier_points(const SegmentWindow<T>& w, int d, const T& e, const T& o, Point<T> q[3]) {
  const int j = w.span;
  const auto level = [&](std::vector<Point<T>>& work, int r, const T& t) {
    for (int i = d; i >= r; --i) {  // as blossom_span's level r
      const int g = j - d + 1 + i;
      const T& lo = w.knots[g - 1];
      const T& hi = w.knots[g + d - r];
      const T alpha = (t - lo) / (hi - lo);
      const T beta = T(1) - alpha;
      work[i] = beta * work[i - 1] + alpha * work[i];
    }
  };
  std::vector<Point<T>> work(w.points.begin() + (j - d + 1), w.points.begin() + (j + 2));
  for (int r = 1; r <= d - 2; ++r) level(work, r, e);
  std::vector<Point<T>> two = work;  // f(e^{d-2}, knots)
  level(work, d - 1, e);
  std::vector<Point<T>> one = work;  // f(e^{d-1}, knots)
  level(work, d, e);
  q[0] = work[d];
  level(one, d, o);
  q[1] = one[d];
  level(two, d - 1, o);
  level(two, d, o);
  q[2] = two[d];
}

// The end curvature's terms of segment s at its start (side 0) or end
// (side 1): end_terms (decide.hpp) of the first three Bezier points read from
// that end, Cartesian or homogeneous (any weight signs; not at a pole), with
// A negated at the end (read backwards the turning sense flips). Exact for
// T = Rational.
template <class T>
EndTerms<T> end_curvature(const BSpline& spline, const Segment& s, int side) {
  const int d = spline.degree();
  const SegmentWindow<T> w = segment_window<T>(spline, s);
  const T e = side == 0 ? T(s.a) : T(s.b);
  const T o = side == 0 ? T(s.b) : T(s.a);
  // The k-th Bezier point from that end: the blossom at (e^{d-k}, o^k).
  const auto args = [&](int k) {
    std::vector<T> a(d, e);
    for (int i = d - k; i < d; ++i) a[i] = o;
    return a;
  };
  EndTerms<T> out;
  if (spline.is_rational()) {
    // The blossom of the homogeneous points (w x, w y, w).
    const std::vector<HPoint<T>> H = homogeneous_window_points<T>(spline, s);
    HPoint<T> h[3];
    for (int k = 0; k < 3; ++k) h[k] = blossom_span(w.knots, H, d, w.span, args(k).data());
    out = end_terms<T>(h[0], h[1], h[2]);
  } else if (std::is_same_v<T, Rational> && d >= 2 && bezier_window(spline, s)) {
    // A Bezier window (extract.hpp): the k-th Bezier point from the end is
    // control point k (side 0) or d-k (side 1), exactly.
    const auto& P = w.points;
    out = side == 0 ? end_terms<T>(P[0], P[1], P[2]) : end_terms<T>(P[d], P[d - 1], P[d - 2]);
  } else if (std::is_same_v<T, DoubleWord> && d >= 2) {
    Point<T> q[3];
    end_bezier_points<T>(w, d, e, o, q);
    out = end_terms<T>(q[0], q[1], q[2]);
  } else {
    Point<T> q[3];
    // A Bezier span's Bezier points are its control points where that is
    // bit for bit the blossom (values and Tracked bounds: bezier_span_points).
    const std::optional<std::vector<Point<T>>> b =
        d >= 2 ? bezier_span_points(w.knots, w.points, d, w.span, T(s.a), T(s.b)) : std::nullopt;
    for (int k = 0; k < 3; ++k)
      q[k] = b ? (*b)[static_cast<std::size_t>(side == 0 ? k : d - k)]
               : blossom_span(w.knots, w.points, d, w.span, args(k).data());
    out = end_terms<T>(q[0], q[1], q[2]);
  }
  if (side == 1) out.A = T(0) - out.A;
  return out;
}

// The end terms of one segment end, each kind computed at most once: a
// joint asks for the certified curvature, the jump sign and the tangent
// angle of the same two ends (the exact ones are GMP rationals, the most
// expensive part of a glyph's joints). The values are those of
// end_curvature, so every result is unchanged.
class EndCache {
 public:
  EndCache(const BSpline& spline, const Segment& s, int side) : spline_(spline), s_(s), side_(side) {}
  /// Error-bounded, and exact (bound 0) where every operation was (tracked.hpp).
  const EndTerms<Tracked>& tracked() {
    if (!tracked_) tracked_ = end_curvature<Tracked>(spline_, s_, side_);
    return *tracked_;
  }
  const EndTerms<Rational>& exact() {
    if (!exact_) exact_ = end_curvature<Rational>(spline_, s_, side_);
    return *exact_;
  }
  /// Double-word, error-bounded (double_word.hpp).
  const EndTerms<DoubleWord>& wide() {
    if (!wide_) wide_ = end_curvature<DoubleWord>(spline_, s_, side_);
    return *wide_;
  }

 private:
  const BSpline& spline_;
  const Segment& s_;
  int side_;
  std::optional<EndTerms<Tracked>> tracked_;
  std::optional<EndTerms<Rational>> exact_;
  std::optional<EndTerms<DoubleWord>> wide_;
};

// Relative error bound below which the error-bounded A and G are used as
// they are: then kappa = c A / G / sqrt(G) in double is within
// 2.5 * 2^-40 + 8u < kKappaRelError of the exact value.
constexpr double kBoundedRel = 0x1p-40;

bool tight(const Tracked& x) { return (x.v == 0 && x.e == 0) || x.e <= kBoundedRel * std::fabs(x.v); }

double kappa_from(double c, double A, double G) { return c * A / G / std::sqrt(G); }

double to_double(const Rational& x) { return x.get_d(); }  // truncation: relative error < 2^-52

// Angle in degrees between the forward end tangent of the left segment (-aL)
// and the start tangent of the right one (aR), exactly 0 when they are
// parallel and point the same way (exact rationals: this runs at C0 knots).
double tangent_angle_deg(EndCache& left, EndCache& right) {
  if (fast_paths_enabled()) {
    // Exact in double (bound 0): the same values the rationals round to.
    const Point<Tracked>& l = left.tracked().a;
    const Point<Tracked>& r = right.tracked().a;
    const Tracked dt = det(r, l), dp = Tracked(0) - dot(l, r);
    if (dt.exact() && dp.exact()) {
      if (dt.v == 0 && dp.v > 0) return 0.0;
      return std::atan2(std::fabs(dt.v), dp.v) * (180.0 / std::numbers::pi);
    }
  }
  const Point<Rational>& l = left.exact().a;
  const Point<Rational>& r = right.exact().a;
  const Rational dt = det(r, l), dp = Rational(0) - dot(l, r);  // det(-l, r) = det(r, l)
  if (sgn(dt) == 0 && sgn(dp) > 0) return 0.0;
  return std::atan2(std::fabs(to_double(dt)), to_double(dp)) * (180.0 / std::numbers::pi);
}

}  // namespace

const char* shape_class(const SegmentShape& s) {
  if (s.pole) return "pole";
  return s.cusp ? "cusp" : (s.straight ? "straight" : "regular");
}

std::vector<double> segment_poles(const BSpline& spline, const Segment& s) {
  if (!spline.is_rational()) return {};
  Bernstein<Bounded> wb;
  for (const HPoint<Bounded>& h : segment_homogeneous_points<Bounded>(spline, s)) wb.push_back(h.z);
  if (strict_sign(wb) != 0) return {};  // most spans: every coefficient certainly of one sign
  Bernstein<Rational> w;
  for (const HPoint<Rational>& h : segment_homogeneous_points<Rational>(spline, s)) w.push_back(h.z);
  if (strict_sign(w) != 0) return {};
  if (is_zero(w)) return {s.a, s.b};
  std::vector<double> out;
  const Rational a(s.a), len = Rational(s.b) - Rational(s.a);
  for (const RootInterval& r : isolate_roots(w)) {
    const Rational t = r.exact() ? r.lo : Scalar<Rational>::half(r.lo + r.hi);
    out.push_back(nearest_double(Rational(a + len * t)));
  }
  return out;
}

bool has_pole(const BSpline& spline) {
  for (const Segment& s : spline.segments())
    if (!segment_poles(spline, s).empty()) return true;
  return false;
}

SegmentClass straight_class() {
  SegmentClass c;
  c.monotonicity = {Curvature::constant, 0};
  c.inflection = {Inflection::present, 0, 0};
  c.exact_used = true;  // decided on exact coefficients, as classify_segment's exact fallback does
  return c;
}

SegmentClass pole_class() {
  SegmentClass c;
  c.monotonicity.curvature = Curvature::non_monotone;
  c.inflection.inflection = Inflection::present;
  return c;
}

int weight_sign(const BSpline& spline, const Segment& s) {
  if (!spline.is_rational()) return 1;
  const Bounded w0 = segment_homogeneous_points<Bounded>(spline, s).front().z;
  const int quick = certain_sign(w0);
  if (quick == 1 || quick == -1) return quick;
  return sgn(segment_homogeneous_points<Rational>(spline, s).front().z);
}

const char* kappa_zero_at(const SegmentShape& s) {
  if (s.kappa_zero_start && s.kappa_zero_end) return "both";
  if (s.kappa_zero_start) return "start";
  if (s.kappa_zero_end) return "end";
  return "none";
}

namespace {

// The curvature's sign polynomial of a segment: eta = det(P', P''), or for a
// rational segment D = det(H, H', H'') (kappa = W^3 D / |h|^3, W != 0 of one
// sign: the caller multiplies by weight_sign); the
// zero polynomial as zero coefficients.
template <class T>
Bernstein<T> curvature_sign_polynomial(const BSpline& spline, const Segment& s) {
  if (!spline.is_rational()) return eta_bernstein<T>(segment_bezier_points<T>(spline, s));
  const Bernstein<T> d = rational_d_bernstein<T>(segment_homogeneous_points<T>(spline, s));
  return d.empty() ? Bernstein<T>(3 * spline.degree() - 5, T(0)) : d;
}

// A polynomial >= 0 that is zero exactly where the tangent is: |P'|^2, or h.h.
Bernstein<Rational> speed_polynomial(const BSpline& spline, const Segment& s) {
  if (!spline.is_rational()) return speed2_bernstein<Rational>(segment_bezier_points<Rational>(spline, s));
  return rational_speed2_bernstein<Rational>(segment_homogeneous_points<Rational>(spline, s));
}

// Whether eta (error-bounded coefficients whose two ends are certainly of
// the same non-zero sign) changes sign strictly inside [0, 1]: halving until
// each piece is certainly of one sign (no root) or has certainly opposite
// signs at its ends (an odd number of sign changes inside it). Inflection::
// undecided when a piece is still open at level kShapeDepth (a touching zero,
// a zero at a halving point, or bounds too wide): then the exact path decides.
constexpr int kShapeDepth = 20;

Inflection halving_inflection(const Bernstein<Bounded>& c, int level) {
  if (strict_sign(c) != 0) return Inflection::none;
  const int s0 = certain_sign(c.front()), sn = certain_sign(c.back());
  if ((s0 == 1 || s0 == -1) && (sn == 1 || sn == -1) && s0 != sn) return Inflection::present;
  if (level >= kShapeDepth) return Inflection::undecided;
  Bernstein<Bounded> left(c.size()), right(c.size()), work(c.size());
  bernstein_halve(c.data(), c.size(), left.data(), right.data(), work.data());
  const Inflection l = halving_inflection(left, level + 1);
  if (l == Inflection::present) return l;
  const Inflection r = halving_inflection(right, level + 1);
  if (r == Inflection::present) return r;
  return l == Inflection::none && r == Inflection::none ? Inflection::none : Inflection::undecided;
}

// segment_shape of a polynomial segment from exactness-tracked Bezier points
// (tracked.hpp), where that decides every field as the exact path would;
// nullopt otherwise. Decided here: eta certainly of one sign (no zero of eta,
// hence none of P'); eta certainly 0 (straight) with |P'|^2 certainly
// positive (no cusp); and eta certainly non-zero at both ends with |P'|^2
// certainly positive, the inflection found by halving_inflection.
std::optional<SegmentShape> fast_shape(const BSpline& spline, const Segment& s) {
  const std::vector<Point<Tracked>> P = segment_bezier_points<Tracked>(spline, s);
  const Bernstein<Tracked> eta = eta_bernstein<Tracked>(P);
  SegmentShape out;
  if (const int quick = strict_sign(eta); quick != 0) {
    out.kappa_sign = quick;
    return out;
  }
  // P' = 0 somewhere only if some coefficient of |P'|^2 is not certainly > 0.
  if (strict_sign(speed2_bernstein<Tracked>(P)) != 1) return std::nullopt;
  if (certainly_zero(eta)) {
    out.straight = true;
    return out;
  }
  const int s0 = certain_sign(eta.front()), sn = certain_sign(eta.back());
  if (!((s0 == 1 || s0 == -1) && (sn == 1 || sn == -1))) return std::nullopt;
  out.kappa_sign = s0;
  out.inflection = s0 != sn ? Inflection::present : halving_inflection(to_bounded(eta), 0);
  if (out.inflection == Inflection::undecided) return std::nullopt;
  return out;
}

}  // namespace

SegmentShape segment_shape(const BSpline& spline, const Segment& s) {
  const bool fast = fast_paths_enabled();
  if (fast && !spline.is_rational())
    if (std::optional<SegmentShape> quick = fast_shape(spline, s)) return *quick;
  SegmentShape out;
  out.poles = segment_poles(spline, s);
  out.pole = !out.poles.empty();
  if (out.pole) {
    out.inflection = Inflection::present;  // forced, as pole_class()
    return out;
  }
  // kappa = W^3 D / |h|^3: D's sign times W's (one sign on the span).
  const int w_sign = weight_sign(spline, s);
  // Most segments: eta certainly of one sign on [0, 1] (so no zero of eta,
  // hence no zero of P' either, as eta = det(P', P'')).
  const int quick = fast ? strict_sign(curvature_sign_polynomial<Bounded>(spline, s)) : 0;
  if (quick != 0) {
    out.kappa_sign = w_sign * quick;
    return out;
  }
  Bernstein<Rational> eta, g;  // g >= 0: zero exactly where P' = 0
  if (!spline.is_rational()) {  // the exact Bezier points extracted once for both
    const std::vector<Point<Rational>> P = segment_bezier_points<Rational>(spline, s);
    eta = eta_bernstein<Rational>(P);
    g = speed2_bernstein<Rational>(P);
  } else {
    eta = curvature_sign_polynomial<Rational>(spline, s);
    g = speed_polynomial(spline, s);
  }
  const RootOptions isolate_only{1.0};
  out.cusp = strict_sign(g) == 0 && (is_zero(g) || !isolate_roots(g, isolate_only).empty());
  out.straight = is_zero(eta);
  if (out.straight) return out;
  // eta = 0 at an end means zero curvature only where the tangent is not
  // zero there (g(0) = |P'(0)|^2 is its first coefficient): at a zero
  // tangent the curvature is unbounded instead (a cusp).
  out.kappa_zero_start = sgn(eta.front()) == 0 && sgn(g.front()) != 0;
  out.kappa_zero_end = sgn(eta.back()) == 0 && sgn(g.back()) != 0;
  out.kappa_sign = w_sign * sign_at_start(eta);
  for (const RootInterval& r : isolate_roots(eta, isolate_only)) {
    const bool at_end = r.exact() && (sgn(r.lo) == 0 || r.lo == 1);
    if (r.sign_change() && !at_end) out.inflection = Inflection::present;
  }
  return out;
}

void validate(const ContinuityTolerances& t) {
  auto text = [](double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  };
  if (!(t.angle_deg >= 0 && t.angle_deg < 180))
    throw InputFieldError(field("angle_deg") + " " + text(t.angle_deg) + " is outside [0, 180) degrees");
  if (!(t.curvature_rel >= 0 && t.curvature_rel <= 1))
    throw InputFieldError(field("curvature_rel") + " " + text(t.curvature_rel) + " is outside [0, 1]");
}

namespace {

double certified_end_curvature(const BSpline& spline, EndCache& end) {
  const double c = (spline.degree() - 1.0) / spline.degree();
  if (fast_paths_enabled()) {
    const EndTerms<Tracked>& b = end.tracked();
    // + 0.0: an exact zero is +0, as the rational's rounding gives it.
    if (tight(b.A) && b.G.v > 0 && tight(b.G)) return kappa_from(c, b.A.v + 0.0, b.G.v);
    // The exact path's value below is kappa_from of the truncations of A and
    // G: a double-word enclosure that pins both gives it without GMP
    // (polynomial spans: end_terms of homogeneous points branches on signs).
    if (!spline.is_rational()) {
      const EndTerms<DoubleWord>& w = end.wide();
      const std::optional<double> A = w.A.truncated(), G = w.G.truncated();
      if (A && G && *G > 0) return kappa_from(c, *A, *G);
    }
  }
  const EndTerms<Rational>& x = end.exact();
  if (sgn(x.G) == 0) return std::numeric_limits<double>::quiet_NaN();  // a zero tangent
  return kappa_from(c, to_double(x.A), to_double(x.G));
}

int curvature_jump_sign(EndCache& left, EndCache& right) {
  if (fast_paths_enabled()) {
    const EndTerms<Tracked>& bl = left.tracked();
    const EndTerms<Tracked>& br = right.tracked();
    const int quick = jump_sign<Tracked>(bl.A, bl.G, br.A, br.G);
    if (quick != kSignUnknown) return quick;
  }
  const EndTerms<Rational>& L = left.exact();
  const EndTerms<Rational>& R = right.exact();
  return jump_sign<Rational>(L.A, L.G, R.A, R.G);
}

}  // namespace

double certified_end_curvature(const BSpline& spline, const Segment& s, int side) {
  EndCache end(spline, s, side);
  return certified_end_curvature(spline, end);
}

int curvature_jump_sign(const BSpline& spline, const Segment& left, const Segment& right) {
  EndCache l(spline, left, 1), r(spline, right, 0);
  return curvature_jump_sign(l, r);
}

std::vector<SegmentClass> exact_inflection_classes(const std::vector<SegmentClass>& segments,
                                                   const std::vector<SegmentShape>& shapes) {
  CMR_CHECK(segments.size() == shapes.size());
  std::vector<SegmentClass> out = segments;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const SegmentShape& sh = shapes[i];
    out[i].inflection = {sh.inflection, 0, sh.inflection == Inflection::none ? sh.kappa_sign : 0};
  }
  return out;
}

SegmentClass neutral_class() {
  SegmentClass c;
  c.monotonicity.curvature = Curvature::constant;
  c.inflection.inflection = Inflection::none;
  c.inflection.kappa_sign = 0;
  return c;
}

Direction part_verdict(const std::vector<SegmentClass>& segments, const std::vector<Joint>& joints, int first,
                       int last, Mode mode, std::vector<int>* conflicts) {
  bool inc = false, dec = false, undecided = false, none = false;
  int kappa_sign = 0;
  for (int i = first; i < last; ++i) {
    const SegmentClass& c = segments[i];
    switch (c.monotonicity.curvature) {
      case Curvature::increasing: inc = true; break;
      case Curvature::decreasing: dec = true; break;
      case Curvature::non_monotone: none = true; break;
      case Curvature::undecided: undecided = true; break;
      case Curvature::constant: break;
    }
    if (mode == Mode::cmr) {
      switch (c.inflection.inflection) {
        case Inflection::present: none = true; break;
        case Inflection::undecided: undecided = true; break;
        case Inflection::none:
          // A sign change at a joint, or across straight segments (sign 0,
          // skipped), is an inflection too. Algorithm 2's "none" always has a
          // sign; the exact reading gives 0 to straight segments.
          if (c.inflection.kappa_sign == 0) break;
          if (kappa_sign != 0 && c.inflection.kappa_sign != kappa_sign) none = true;
          kappa_sign = c.inflection.kappa_sign;
          break;
      }
    }
  }
  if (none || (inc && dec)) return Direction::none;
  // Jumps at non-C^2 joints inside the part must follow the direction.
  bool jump_up = false, jump_down = false;
  for (int i = first + 1; i < last; ++i) {
    const Joint& j = joints[i - 1];
    jump_up = jump_up || j.jump > 0;
    jump_down = jump_down || j.jump < 0;
    if ((j.jump > 0 && dec) || (j.jump < 0 && inc)) {
      if (conflicts) conflicts->push_back(j.index);
      none = true;
    }
  }
  if (none || (jump_up && jump_down)) return Direction::none;
  if (undecided) return Direction::undecided;
  if (dec || jump_down) return Direction::decreasing;
  return Direction::increasing;  // inc, or all constant (Algorithm 1 checks (1) first)
}

Split combine_split(Direction before, Direction after) {
  if (before == Direction::none || after == Direction::none) return Split::none;
  if (before == Direction::undecided || after == Direction::undecided) return Split::undecided;
  const bool a = before == Direction::increasing, b = after == Direction::increasing;
  return a ? (b ? Split::inc_inc : Split::inc_dec) : (b ? Split::dec_inc : Split::dec_dec);
}

Alternation alternation_verdict(const std::vector<Direction>& groups) {
  bool undecided = false;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (groups[g] == Direction::none) return Alternation::fail;
    undecided = undecided || groups[g] == Direction::undecided;
    if (g > 0 && groups[g] == groups[g - 1] && groups[g] != Direction::undecided) return Alternation::fail;
  }
  if (undecided) return Alternation::undecided;
  return groups.front() == Direction::increasing ? Alternation::first_increasing : Alternation::first_decreasing;
}

EachPiece each_piece_verdict(const std::vector<Direction>& groups) {
  bool undecided = false;
  for (Direction g : groups) {
    if (g == Direction::none) return EachPiece::fail;
    undecided = undecided || g == Direction::undecided;
  }
  return undecided ? EachPiece::undecided : EachPiece::monotone;
}

Joint joint_between(const BSpline& spline, int left, int right, const ContinuityTolerances& tolerances) {
  const Segment& L = spline.segments()[left];
  const Segment& R = spline.segments()[right];
  Joint j;
  j.index = right == 0 ? spline.segment_count() : right;
  j.knot = right == 0 ? L.b : R.a;
  j.multiplicity = spline.multiplicity(R.a);
  j.continuity = spline.degree() - j.multiplicity;
  if (const std::vector<double> at = segment_poles(spline, L); !at.empty() && at.back() == L.b) {
    // W = 0 at the knot (a root at a span's end is found exactly): the curve
    // passes through infinity at the joint, nothing to measure there.
    j.pole = true;
    j.kappa_left = j.kappa_right = j.angle_deg = std::numeric_limits<double>::quiet_NaN();
    return j;
  }
  EndCache end_l(spline, L, 1), end_r(spline, R, 0);  // each end's terms computed once for all below
  j.kappa_left = certified_end_curvature(spline, end_l);
  j.kappa_right = certified_end_curvature(spline, end_r);
  j.zero_tangent = std::isnan(j.kappa_left) || std::isnan(j.kappa_right);
  j.jump = j.continuity >= 2 ? 0 : curvature_jump_sign(end_l, end_r);
  if (j.zero_tangent) {
    j.angle_deg = std::numeric_limits<double>::quiet_NaN();
  } else {
    // C^1 by the knots: the end derivatives are equal vectors, angle 0.
    j.angle_deg = j.continuity >= 1 ? 0.0 : tangent_angle_deg(end_l, end_r);
    j.g1 = j.angle_deg <= tolerances.angle_deg;
    // Equal curvature: exactly (C^2, or an exact jump of 0), or within the tolerance.
    const double diff = std::fabs(j.kappa_right - j.kappa_left);
    const double scale = std::max(std::fabs(j.kappa_left), std::fabs(j.kappa_right));
    j.g2 = j.g1 && (j.continuity >= 2 || j.jump == 0 || diff <= tolerances.curvature_rel * scale);
  }
  return j;
}

AnalyzeParts default_analyze_parts() { return {segment_shape, classify_segment, joint_between}; }

SplineAnalysis analyze(const BSpline& spline, const AnalyzeOptions& options) {
  return analyze(spline, options, default_analyze_parts());
}

SplineAnalysis analyze(const BSpline& spline, const AnalyzeOptions& options, const AnalyzeParts& parts) {
  SplineAnalysis out = start_analysis(spline, options);
  for (int i = 0; i < spline.segment_count(); ++i) analyze_span(out, spline, options, parts, i);
  finish_analysis(out, spline, options, parts);
  return out;
}

SplineAnalysis analyze_on_threads(const BSpline& spline, const AnalyzeOptions& options, int threads,
                                  const std::atomic<bool>* cancel) {
  constexpr int kChunk = 256;  // spans per job: small enough to answer a cancel within milliseconds
  const AnalyzeParts parts = default_analyze_parts();
  SplineAnalysis out = start_analysis(spline, options);
  const int n = spline.segment_count();
  parallel_for(static_cast<std::size_t>((n + kChunk - 1) / kChunk), threads, [&](std::size_t k) {
    if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) throw Cancelled();
    const int first = static_cast<int>(k) * kChunk;
    for (int i = first; i < std::min(n, first + kChunk); ++i) analyze_span(out, spline, options, parts, i);
  });
  if (cancel != nullptr && cancel->load()) throw Cancelled();
  finish_analysis(out, spline, options, parts);
  return out;
}

SplineAnalysis start_analysis(const BSpline& spline, const AnalyzeOptions& options) {
  const int N = spline.segment_count();
  const SegmentRange range = judged_range(options.segments, N);
  if (options.split) validate_cuts({*options.split}, range, N);
  validate_cuts(options.splits, range, N);
  if (options.split && !options.splits.empty()) throw InputError("give one split joint or a list of them, not both");
  if (options.split && options.each_piece)
    throw InputFieldError(field("split") + " and " + field("each_piece") + " exclude each other: give the joints to " +
                          field("each_piece"));
  if (options.classify.max_depth < 0 || options.classify.max_depth > kMaxDepth)
    throw InputError("depth " + std::to_string(options.classify.max_depth) + " is outside 0.." +
                     std::to_string(kMaxDepth));
  validate(options.continuity);
  SplineAnalysis out;
  out.range = range;
  out.segments.resize(N);
  out.shapes.resize(N);
  out.joints.resize(N - 1);
  return out;
}

void analyze_span(SplineAnalysis& out, const BSpline& spline, const AnalyzeOptions& options, const AnalyzeParts& parts,
                  int i) {
  ClassifyOptions co = options.classify;
  co.inflection = true;  // CMR verdicts always need Algorithm 2
  const Segment& s = spline.segments()[i];
  out.shapes[i] = parts.shape(spline, s);
  const SegmentShape& shape = out.shapes[i];
  // A straight polynomial segment (eta == 0, decided exactly above): lambda
  // == 0 too, and Algorithms 1 and 2 on the exact coefficients stop at level
  // 0 with "constant" and "inflection" (eta_0 eta_n = 0), which is what
  // classify_segment finds through its exact fallback (error bounds never
  // prove a zero); the class is written down instead of recomputed.
  const bool straight = fast_paths_enabled() && shape.straight && !spline.is_rational();
  out.segments[i] = !out.judged(s.index) ? SegmentClass{}
                    : shape.pole         ? pole_class()
                    : straight           ? straight_class()
                                         : parts.classify(spline, s, co);
  if (i > 0) out.joints[i - 1] = parts.joint(spline, i - 1, i, options.continuity);
}

void finish_analysis(SplineAnalysis& out, const BSpline& spline, const AnalyzeOptions& options,
                     const AnalyzeParts& parts) {
  const int N = spline.segment_count();
  for (int i = 0; i < N; ++i) {
    out.exact_segments += out.segments[i].exact_used ? 1 : 0;
    out.cusp = out.cusp || out.shapes[i].cusp;
    out.pole = out.pole || out.shapes[i].pole;
  }
  if (spline.closed()) out.seam = parts.joint(spline, N - 1, 0, options.continuity);
  const std::vector<SegmentClass> reported = exact_inflection_classes(out.segments, out.shapes);
  const int first = out.range.first, end = out.range.last + 1;
  // The whole period of a closed spline without split joints: the seam is a
  // joint inside the part (a neutral class after the last segment).
  const bool around =
      out.seam && first == 0 && end == N && !options.split && options.splits.empty() && !options.each_piece;
  const auto whole = [&](const std::vector<SegmentClass>& classes, Mode mode, std::vector<int>* conflicts) {
    if (!around) return part_verdict(classes, out.joints, first, end, mode, conflicts);
    std::vector<SegmentClass> c = classes;
    c.push_back(neutral_class());
    std::vector<Joint> j = out.joints;
    j.push_back(*out.seam);
    return part_verdict(c, j, 0, N + 1, mode, conflicts);
  };
  out.cmrwi = whole(out.segments, Mode::cmrwi, &out.joint_conflicts);
  out.cmr = whole(reported, Mode::cmr, nullptr);
  out.cmr_algorithm2 = whole(out.segments, Mode::cmr, nullptr);
  if (options.split) {
    const int s = *options.split;
    out.split = combine_split(part_verdict(reported, out.joints, first, s, options.split_mode),
                              part_verdict(reported, out.joints, s, end, options.split_mode));
  }
  if (options.each_piece || !options.splits.empty()) {
    out.cuts = options.each_piece ? each_piece_cuts(out.range, options.splits) : options.splits;
    for (const auto& [a, b] : segment_groups(out.range, out.cuts))
      out.groups.push_back(part_verdict(reported, out.joints, a, b, options.split_mode));
    if (options.each_piece) out.each_piece = each_piece_verdict(out.groups);
    else out.alternation = alternation_verdict(out.groups);
  }
}

}  // namespace cmr
