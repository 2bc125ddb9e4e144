#include "bezierize/classify.hpp"

#include "bezierize/extract.hpp"
#include "bezierize/fast_lambda.hpp"

#include <algorithm>
#include <cmath>
#include "bezierize/lambda.hpp"

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

namespace {

// Three-valued truth for conditions on coefficients whose sign may be unknown.
enum class Truth { no, yes, unknown };

struct SignCounts {
  int pos = 0, neg = 0, zero = 0, unknown = 0;
  int first = 0, last = 0;  // signs of c_0 and c_n (kSignUnknown if unknown)
};

template <class T>
SignCounts count_signs(const T* c, int n1) {
  SignCounts s;
  for (int i = 0; i < n1; ++i) {
    const int g = Scalar<T>::sign(c[i]);
    if (i == 0) s.first = g;
    if (i == n1 - 1) s.last = g;
    if (g == kSignUnknown) ++s.unknown;
    else if (g > 0) ++s.pos;
    else if (g < 0) ++s.neg;
    else ++s.zero;
  }
  return s;
}


// Depth-first traversal shared by both algorithms, with an explicit stack of at
// most max_depth + 1 pending pieces. `decide(c, n1)` judges one piece; `visit`
// folds its outcome in and returns true to stop early.
template <class T, class Decide, class Visit>
bool traverse(const Bernstein<T>& c, int max_depth, Decide decide, Visit visit) {
  const int n1 = static_cast<int>(c.size());
  std::vector<T> stack(static_cast<std::size_t>(max_depth + 2) * n1);
  std::vector<int> levels(max_depth + 2);
  std::vector<T> left(n1), right(n1), work(n1);
  std::copy(c.begin(), c.end(), stack.begin());
  levels[0] = 0;
  int sp = 1;
  while (sp > 0) {
    --sp;
    T* cur = &stack[static_cast<std::size_t>(sp) * n1];
    const int level = levels[sp];
    const Piece p = decide(cur, n1);
    if (p == Piece::uncertain) return false;
    if (p == Piece::split && level < max_depth) {
      bernstein_halve(cur, n1, left.data(), right.data(), work.data());
      std::copy(right.begin(), right.end(), cur);
      std::copy(left.begin(), left.end(), cur + n1);
      levels[sp] = levels[sp + 1] = level + 1;
      sp += 2;  // left on top: pieces are visited in parameter order
      continue;
    }
    if (visit(p, level)) break;  // p == split here means: undecided at level D
  }
  return true;
}

template <class T>
Piece monotonicity_piece(const T* c, int n1) {
  const SignCounts s = count_signs(c, n1);
  const Truth ge = s.neg > 0 ? Truth::no : (s.unknown > 0 ? Truth::unknown : Truth::yes);
  const Truth le = s.pos > 0 ? Truth::no : (s.unknown > 0 ? Truth::unknown : Truth::yes);
  Truth ends;  // condition (3): xi_0 * xi_last < 0
  if (s.first == kSignUnknown || s.last == kSignUnknown) {
    ends = (s.first == 0 || s.last == 0) ? Truth::no : Truth::unknown;
  } else {
    ends = (s.first * s.last < 0) ? Truth::yes : Truth::no;
  }
  if (ends == Truth::yes) return Piece::non_monotone;
  if (ge == Truth::yes && le == Truth::yes) return Piece::zero;
  if (ge == Truth::yes) return Piece::increasing;
  if (le == Truth::yes) return Piece::decreasing;
  if (ge == Truth::unknown || le == Truth::unknown || ends == Truth::unknown) return Piece::uncertain;
  return Piece::split;
}

template <class T>
Piece inflection_piece(const T* c, int n1) {
  const SignCounts s = count_signs(c, n1);
  Truth touches;  // condition (1): nu_0 * nu_last <= 0
  if (s.first == 0 || s.last == 0) touches = Truth::yes;
  else if (s.first == kSignUnknown || s.last == kSignUnknown) touches = Truth::unknown;
  else touches = (s.first * s.last < 0) ? Truth::yes : Truth::no;
  if (touches == Truth::yes) return Piece::inflection;
  if (touches == Truth::unknown) return Piece::uncertain;
  if (s.pos == n1 || s.neg == n1) return Piece::no_inflection;  // condition (2)
  const bool not_all_pos = s.neg + s.zero > 0, not_all_neg = s.pos + s.zero > 0;
  if (not_all_pos && not_all_neg) return Piece::split;
  return Piece::uncertain;
}

}  // namespace

template <class T>
std::optional<MonotonicityResult> algorithm1(const Bernstein<T>& xi, int max_depth) {
  CMR_CHECK(!xi.empty() && max_depth >= 0);
  MonotonicityFold fold;
  if (!traverse(xi, max_depth, monotonicity_piece<T>, [&](Piece p, int level) { return fold.visit(p, level); }))
    return std::nullopt;
  return fold.result(max_depth);
}

template <class T>
std::optional<InflectionResult> algorithm2(const Bernstein<T>& nu, int max_depth) {
  CMR_CHECK(!nu.empty() && max_depth >= 0);
  InflectionFold fold;
  if (!traverse(nu, max_depth, inflection_piece<T>, [&](Piece p, int level) { return fold.visit(p, level); }))
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

SegmentClass finish(std::optional<MonotonicityResult> mono, std::optional<InflectionResult> infl, bool exact) {
  SegmentClass out;
  out.monotonicity = *mono;
  if (infl) out.inflection = *infl;
  out.exact_used = exact;
  return out;
}

// Algorithms 1 and 2 on double coefficients with one error bound per piece,
// without allocating: the same traversal and decisions as algorithm1<T>.
// A piece's bound E covers every coefficient; halving averages neighbours, so
// a child's coefficients are within E plus the rounding of n averaging steps,
// each at most u max|c| (convex combinations do not grow max|c|): the child
// gets E + n u max|c| (1 + 2^-20) + tiny. Degrees up to kFastMaxDegree,
// depths up to 30.
constexpr int kFastCoefficients = 4 * kFastMaxDegree - 6;

template <bool Inflection, int N1>
int fast_piece(const double* v, double e, int runtime_n1) {
  const int n1 = N1 > 0 ? N1 : runtime_n1;
  int pos = 0, neg = 0, unk = 0;
  for (int i = 0; i < n1; ++i) {
    const bool certain = std::fabs(v[i]) > e;
    unk += !certain;
    pos += certain && v[i] > 0;
    neg += certain && v[i] < 0;
  }
  const auto sign_of = [&](double x) { return std::fabs(x) > e ? (x > 0 ? 1 : -1) : kSignUnknown; };
  const int first = sign_of(v[0]), last = sign_of(v[n1 - 1]);
  const bool ends_known = first != kSignUnknown && last != kSignUnknown;
  if (Inflection) {
    if (!ends_known) return static_cast<int>(Piece::uncertain);
    if (first * last < 0) return static_cast<int>(Piece::inflection);
    if (pos == n1 || neg == n1) return static_cast<int>(Piece::no_inflection);
    if (pos > 0 && neg > 0) return static_cast<int>(Piece::split);
    return static_cast<int>(Piece::uncertain);
  }
  if (ends_known && first * last < 0) return static_cast<int>(Piece::non_monotone);
  const bool ge = neg == 0 && unk == 0, le = pos == 0 && unk == 0;
  if (ge) return static_cast<int>(Piece::increasing);
  if (le) return static_cast<int>(Piece::decreasing);
  if (neg == 0 || pos == 0 || !ends_known) return static_cast<int>(Piece::uncertain);
  return static_cast<int>(Piece::split);
}

// Visits pieces as traverse() does; visit(piece, level) returns true to stop.
template <bool Inflection, int N1, class Visit>
bool fast_traverse(const double* v0, double e0, int runtime_n1, int max_depth, Visit visit) {
  const int n1 = N1 > 0 ? N1 : runtime_n1;
  double sv[32 * kFastCoefficients], se[32];
  int levels[32];
  std::copy(v0, v0 + n1, sv);
  se[0] = e0;
  levels[0] = 0;
  int sp = 1;
  while (sp > 0) {
    --sp;
    double* cv = sv + sp * n1;
    const double e = se[sp];
    const int level = levels[sp];
    const Piece p = static_cast<Piece>(fast_piece<Inflection, N1>(cv, e, n1));
    if (p == Piece::uncertain) return false;
    if (p == Piece::split && level < max_depth) {
      // de Casteljau at 1/2: right half stays at sp, left half above it.
      double w[kFastCoefficients];
      double m = 0;
      for (int i = 0; i < n1; ++i) {
        w[i] = cv[i];
        m = std::max(m, std::fabs(cv[i]));
      }
      double* lv = cv + n1;
      lv[0] = w[0];
      cv[n1 - 1] = w[n1 - 1];
      for (int r = 1; r < n1; ++r) {
        for (int i = 0; i + r < n1; ++i) w[i] = 0.5 * (w[i] + w[i + 1]);
        lv[r] = w[0];
        cv[n1 - 1 - r] = w[n1 - 1 - r];
      }
      se[sp] = se[sp + 1] = e + n1 * (0.5 * Bounded::kRound) * m * (1 + 0x1p-20) + Bounded::kTiny;
      levels[sp] = levels[sp + 1] = level + 1;
      sp += 2;
      continue;
    }
    if (visit(p, level)) break;
  }
  return true;
}

template <int N1>
std::optional<MonotonicityResult> fast_algorithm1_n(const double* v, double e, int n1, int max_depth) {
  // Most segments are decided by the whole segment (level 0): no stack.
  switch (static_cast<Piece>(fast_piece<false, N1>(v, e, n1))) {
    case Piece::non_monotone: return MonotonicityResult{Curvature::non_monotone, 0};
    case Piece::increasing: return MonotonicityResult{Curvature::increasing, 0};
    case Piece::decreasing: return MonotonicityResult{Curvature::decreasing, 0};
    case Piece::uncertain: return std::nullopt;
    default: break;
  }
  MonotonicityFold fold;
  if (!fast_traverse<false, N1>(v, e, n1, max_depth, [&](Piece p, int level) { return fold.visit(p, level); }))
    return std::nullopt;
  return fold.result(max_depth);
}

template <int N1>
std::optional<InflectionResult> fast_algorithm2_n(const double* v, double e, int n1, int max_depth) {
  InflectionFold fold;
  if (!fast_traverse<true, N1>(v, e, n1, max_depth, [&](Piece p, int level) { return fold.visit(p, level); }))
    return std::nullopt;
  return fold.result(max_depth, v[0] > 0 ? 1 : -1);
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
  std::optional<MonotonicityResult> mono;
  std::optional<InflectionResult> infl;
  const int n = static_cast<int>(points.size()) - 1;
  if (n <= kFastMaxDegree) {
    // Plain double with a-priori bounds; most segments are decided at level 0.
    FastCoefficients f;
    fast_lambda_eta(points.data(), n, f);
    if (options.max_depth <= 30) {
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
  classify_points<Bounded>(segment_bezier_points<Bounded>(spline, s), options, mono, infl);
  if (mono && (infl || !options.inflection)) return finish(mono, infl, false);
  // The Bezier points are rounded; the exact path re-extracts them exactly.
  classify_points<Rational>(segment_bezier_points<Rational>(spline, s), options, mono, infl);
  return finish(mono, infl, true);
}

}  // namespace cmr
