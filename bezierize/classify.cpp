#include "bezierize/classify.hpp"
#include "bezierize/algorithms.hpp"
#include "bezierize/decide.hpp"

#include "bezierize/extract.hpp"
#include "bezierize/fast_lambda.hpp"

#include <algorithm>
#include <cmath>
#include "bezierize/lambda.hpp"
#include "bezierize/rational_lambda.hpp"
#include "spline/errors.hpp"
#include "spline/limits.hpp"

namespace cmr {

const char* to_string(Curvature c) {
  switch (c) {
    case Curvature::increasing: return "increasing";
    case Curvature::decreasing: return "decreasing";
    case Curvature::non_monotone: return "non-monotone";
    case Curvature::undecided: return "undecided";
    case Curvature::constant: return "constant";
  }
  return "?";
}

const char* to_string(Inflection i) {
  switch (i) {
    case Inflection::none: return "none";
    case Inflection::present: return "present";
    case Inflection::undecided: return "undecided";
  }
  return "?";
}

const char* to_string(Piece p) {
  switch (p) {
    case Piece::increasing: return "increasing";
    case Piece::decreasing: return "decreasing";
    case Piece::zero: return "zero";
    case Piece::non_monotone: return "non_monotone";
    case Piece::inflection: return "inflection";
    case Piece::no_inflection: return "no_inflection";
    case Piece::split: return "split";
    case Piece::uncertain: return "uncertain";
  }
  return "?";
}

bool MonotonicityFold::visit(Piece p, int level) {
  switch (p) {
    case Piece::zero:  // lambda == 0 on a piece means lambda == 0: seen at level 0
      stop_ = MonotonicityResult{Curvature::constant, level};
      return true;
    case Piece::non_monotone:
      stop_ = MonotonicityResult{Curvature::non_monotone, level};
      return true;
    case Piece::increasing: inc_ = true; break;
    case Piece::decreasing: dec_ = true; break;
    default: undecided_ = true; break;  // still split at level D
  }
  deepest_ = std::max(deepest_, level);
  if (inc_ && dec_) stop_ = MonotonicityResult{Curvature::non_monotone, level};
  return stop_.has_value();
}

MonotonicityResult MonotonicityFold::result(int max_depth) const {
  if (stop_) return *stop_;
  if (undecided_) return {Curvature::undecided, max_depth};
  return {inc_ ? Curvature::increasing : Curvature::decreasing, deepest_};
}

bool InflectionFold::visit(Piece p, int level) {
  if (p == Piece::inflection) {
    stop_ = InflectionResult{Inflection::present, level, 0};
    return true;
  }
  if (p != Piece::no_inflection) undecided_ = true;
  deepest_ = std::max(deepest_, level);
  return false;
}

InflectionResult InflectionFold::result(int max_depth, int kappa_sign) const {
  if (stop_) return *stop_;
  if (undecided_) return {Inflection::undecided, max_depth, 0};
  return {Inflection::none, deepest_, kappa_sign};
}

template <class T>
std::optional<MonotonicityResult> algorithm1(const Bernstein<T>& xi, int max_depth) {
  CMR_CHECK(!xi.empty() && max_depth >= 0);
  BernsteinSource<T> src(xi, max_depth);
  MonotonicityFold fold;
  if (!traverse(src, max_depth, monotonicity_piece, [&](Piece p, int level) { return fold.visit(p, level); }))
    return std::nullopt;
  return fold.result(max_depth);
}

template <class T>
std::optional<InflectionResult> algorithm2(const Bernstein<T>& nu, int max_depth) {
  CMR_CHECK(!nu.empty() && max_depth >= 0);
  BernsteinSource<T> src(nu, max_depth);
  InflectionFold fold;
  if (!traverse(src, max_depth, inflection_piece, [&](Piece p, int level) { return fold.visit(p, level); }))
    return std::nullopt;
  return fold.result(max_depth, Scalar<T>::sign(nu.front()));
}

template std::optional<MonotonicityResult> algorithm1(const Bernstein<double>&, int);
template std::optional<MonotonicityResult> algorithm1(const Bernstein<Bounded>&, int);
template std::optional<MonotonicityResult> algorithm1(const Bernstein<Rational>&, int);
template std::optional<InflectionResult> algorithm2(const Bernstein<double>&, int);
template std::optional<InflectionResult> algorithm2(const Bernstein<Bounded>&, int);
template std::optional<InflectionResult> algorithm2(const Bernstein<Rational>&, int);

namespace {

// Runs both algorithms on Bezier points of scalar type T; fields left empty
// (nullopt) where a decision was uncertain.
template <class T>
void classify_points(const std::vector<Point<T>>& P, const ClassifyOptions& o,
                     std::optional<MonotonicityResult>& mono, std::optional<InflectionResult>& infl) {
  if (!mono) mono = algorithm1(lambda_bernstein<T>(P), o.max_depth);
  if (o.inflection && !infl) infl = algorithm2(eta_bernstein<T>(P), o.max_depth);
}

// The same on a rational segment's homogeneous Bezier points: Algorithm 1 on
// lambda, Algorithm 2 on D (rational_lambda.hpp; sign(kappa) = sign(D)).
template <class T>
void classify_homogeneous(const std::vector<HPoint<T>>& H, const ClassifyOptions& o,
                          std::optional<MonotonicityResult>& mono, std::optional<InflectionResult>& infl) {
  const HomogeneousBezier<T> c = homogeneous_components<T>(H);
  if (!mono) mono = algorithm1(rational_lambda_bernstein<T>(c), o.max_depth);
  if (o.inflection && !infl) infl = algorithm2(rational_d_bernstein<T>(c), o.max_depth);
}

SegmentClass finish(std::optional<MonotonicityResult> mono, std::optional<InflectionResult> infl, bool exact) {
  SegmentClass out;
  out.monotonicity = *mono;
  if (infl) out.inflection = *infl;
  out.exact_used = exact;
  return out;
}

// Algorithms 1 and 2 on double coefficients with one error bound per piece,
// without allocating: a source of the one traversal (decide.hpp).
// A piece's bound E covers every coefficient; halving averages neighbours, so
// a child's coefficients are within E plus the rounding of n averaging steps,
// each at most u max|c| (convex combinations do not grow max|c|): the child
// gets E + n u max|c| (1 + 2^-20) + tiny. Degrees up to kFastMaxDegree,
// depths up to kMaxDepth. N1 > 0 fixes the number of coefficients at compile
// time (cubics), 0 reads it at run time.
constexpr int kFastCoefficients = 4 * kFastMaxDegree - 6;

template <int N1>
class FastSource {
 public:
  FastSource(const double* v, double e, int n1) : cur_(v), e_(e), n1_(N1 > 0 ? N1 : n1) {}
  int size() const { return n1_; }
  /// Certain when |v| > e; certainly 0 only for an exact 0 (e == 0).
  int sign(int k) const {
    const double x = cur_[k];
    if (std::fabs(x) > e_) return x > 0 ? 1 : -1;
    return x == 0 && e_ == 0 ? 0 : kSignUnknown;
  }
  void split(int, int) {
    const int n1 = N1 > 0 ? N1 : n1_;
    double m = 0;
    for (int i = 0; i < n1; ++i) m = std::max(m, std::fabs(cur_[i]));
    e_ += n1 * (0.5 * Bounded::kRound) * m * (1 + 0x1p-20) + Bounded::kTiny;
    double work[kFastCoefficients];
    bernstein_halve(cur_, n1, left_, pending_ + sp_ * n1, work);
    pending_e_[sp_++] = e_;
    cur_ = left_;
  }
  void next(int, int) {
    --sp_;
    cur_ = pending_ + sp_ * (N1 > 0 ? N1 : n1_);
    e_ = pending_e_[sp_];
  }

 private:
  const double* cur_;  // the input (level 0), left_, or a pending slot
  double e_;
  int n1_, sp_ = 0;
  double left_[kFastCoefficients];
  double pending_[kMaxDepth * kFastCoefficients], pending_e_[kMaxDepth];
};

template <int N1>
std::optional<MonotonicityResult> fast_algorithm1_n(const double* v, double e, int n1, int max_depth) {
  FastSource<N1> src(v, e, n1);
  MonotonicityFold fold;
  if (!traverse(src, max_depth, monotonicity_piece, [&](Piece p, int level) { return fold.visit(p, level); }))
    return std::nullopt;
  return fold.result(max_depth);
}

template <int N1>
std::optional<InflectionResult> fast_algorithm2_n(const double* v, double e, int n1, int max_depth) {
  FastSource<N1> src(v, e, n1);
  const int kappa_sign = src.sign(0);  // the whole segment's first coefficient
  InflectionFold fold;
  if (!traverse(src, max_depth, inflection_piece, [&](Piece p, int level) { return fold.visit(p, level); }))
    return std::nullopt;
  return fold.result(max_depth, kappa_sign);
}

// Cubic segments (the common case) get loops of fixed length.
std::optional<MonotonicityResult> fast_algorithm1(const double* v, double e, int n1, int max_depth) {
  return n1 == 6 ? fast_algorithm1_n<6>(v, e, n1, max_depth) : fast_algorithm1_n<0>(v, e, n1, max_depth);
}
std::optional<InflectionResult> fast_algorithm2(const double* v, double e, int n1, int max_depth) {
  return n1 == 3 ? fast_algorithm2_n<3>(v, e, n1, max_depth) : fast_algorithm2_n<0>(v, e, n1, max_depth);
}

template <class T>
std::vector<Point<T>> convert(const std::vector<Vec2>& P) {
  std::vector<Point<T>> out;
  out.reserve(P.size());
  for (const Vec2& p : P) out.push_back(to_point<T>(p));
  return out;
}

}  // namespace

SegmentClass classify_bezier(std::span<const Vec2> points, const ClassifyOptions& options) {
  for (const Vec2& p : points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw InputError("a Bezier control point is not finite");
  std::optional<MonotonicityResult> mono;
  std::optional<InflectionResult> infl;
  const int n = static_cast<int>(points.size()) - 1;
  if (n <= kFastMaxDegree) {
    // Plain double with a-priori bounds; most segments are decided at level 0.
    FastCoefficients f;
    fast_lambda_eta(points.data(), n, f);
    if (options.max_depth <= kMaxDepth) {
      const double xi_err = *std::max_element(f.xi_err.begin(), f.xi_err.begin() + f.n_xi);
      const double nu_err = *std::max_element(f.nu_err.begin(), f.nu_err.begin() + f.n_nu);
      mono = fast_algorithm1(f.xi.data(), xi_err, f.n_xi, options.max_depth);
      if (options.inflection) infl = fast_algorithm2(f.nu.data(), nu_err, f.n_nu, options.max_depth);
    }
    if (mono && (infl || !options.inflection)) return finish(mono, infl, false);
  }
  const std::vector<Vec2> pts(points.begin(), points.end());
  if (!mono || (options.inflection && !infl)) classify_points<Bounded>(convert<Bounded>(pts), options, mono, infl);
  if (mono && (infl || !options.inflection)) return finish(mono, infl, false);
  classify_points<Rational>(convert<Rational>(pts), options, mono, infl);
  return finish(mono, infl, true);
}

SegmentClass classify_segment(const BSpline& spline, const Segment& s, const ClassifyOptions& options) {
  std::optional<MonotonicityResult> mono;
  std::optional<InflectionResult> infl;
  if (spline.is_rational()) {
    // Certified double first, then exact from the double points and weights.
    classify_homogeneous<Bounded>(segment_homogeneous_points<Bounded>(spline, s), options, mono, infl);
    if (mono && (infl || !options.inflection)) return finish(mono, infl, false);
    classify_homogeneous<Rational>(segment_homogeneous_points<Rational>(spline, s), options, mono, infl);
    return finish(mono, infl, true);
  }
  classify_points<Bounded>(segment_bezier_points<Bounded>(spline, s), options, mono, infl);
  if (mono && (infl || !options.inflection)) return finish(mono, infl, false);
  // The Bezier points are rounded; the exact path re-extracts them exactly.
  classify_points<Rational>(segment_bezier_points<Rational>(spline, s), options, mono, infl);
  return finish(mono, infl, true);
}

}  // namespace cmr
