#include "bezierize/region_setup.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include "bezierize/lambda.hpp"
#include "bezierize/poly3.hpp"
#include "spline/errors.hpp"

namespace cmr::detail {

namespace {

double rounded(const Rational& q) { return q.get_d(); }

// The first K coefficients rounded to double. All zeros exactly when the
// polynomial is zero: a non-zero one whose coefficients all underflow gets a
// NaN, which makes every sign uncertain (and the pixel exact) instead of
// passing for a structural zero.
template <std::size_t K>
std::array<double, K> rounded_poly(const Poly3& p) {
  std::array<double, K> r{};
  bool exact_zero = true, all_rounded_zero = true;
  for (std::size_t m = 0; m < K; ++m) {
    r[m] = rounded(p.c[m]);
    exact_zero = exact_zero && sgn(p.c[m]) == 0;
    all_rounded_zero = all_rounded_zero && r[m] == 0;
  }
  if (all_rounded_zero && !exact_zero) r[0] = std::numeric_limits<double>::quiet_NaN();
  return r;
}

// Bernstein coefficients of every subdivision piece down to `levels`, in heap
// order (piece 2^L - 1 + j is [j, j+1] / 2^L), exactly.
std::vector<Bernstein<Poly3>> piece_polynomials(const Bernstein<Poly3>& root, int levels) {
  std::vector<Bernstein<Poly3>> pieces{root};
  const std::size_t n1 = root.size();
  const Poly3 half(Rational(1, 2));
  for (std::size_t p = 0; pieces.size() < (std::size_t{2} << levels) - 1; ++p) {
    Bernstein<Poly3> w = pieces[p], left(n1), right(n1);
    left[0] = w[0];
    right[n1 - 1] = w[n1 - 1];
    for (std::size_t r = 1; r < n1; ++r) {
      for (std::size_t i = 0; i + r < n1; ++i) w[i] = half * (w[i] + w[i + 1]);
      left[r] = w[0];
      right[n1 - 1 - r] = w[n1 - 1 - r];
    }
    pieces.push_back(std::move(left));
    pieces.push_back(std::move(right));
  }
  return pieces;
}

}  // namespace

RegionSetup prepare_region(const BSpline& spline, const RegionOptions& options) {
  validate_region_options(spline, options);
  RegionSetup s{spline, options, {}, {}, {}, {}, {}, {}, false, false, std::min(options.max_depth, kPieceLevels)};
  if (!s.options.view) {
    s.options.view = default_view(spline, options.width, options.height);
    validate_region_options(spline, s.options);  // a default view of huge coordinates can overflow
  }
  s.group.push_back(options.point);
  for (int g : options.with)
    if (std::find(s.group.begin(), s.group.end(), g) == s.group.end()) s.group.push_back(g);
  s.anchor = spline.points()[options.point];

  AnalyzeOptions ao;
  ao.classify.max_depth = options.max_depth;
  const SplineAnalysis a = analyze(spline, ao);
  s.fixed = a.segments;
  s.joints = a.joints;

  const int d = spline.degree(), N = spline.segment_count();
  const int split = options.split.value_or(0);
  std::vector<bool> touched(N, false), needed(N, false);
  for (const SegmentInfluence& si : influence(spline, s.group)) touched[si.segment] = needed[si.segment] = true;
  std::vector<int> varying_joints;
  for (std::size_t j = 0; j < s.joints.size(); ++j) {
    const int idx = s.joints[j].index;
    if (idx == split || s.joints[j].continuity >= 2) continue;  // split joint: jump is free; C2: no jump
    if (!touched[idx - 1] && !touched[idx]) continue;
    varying_joints.push_back(static_cast<int>(j));
    needed[idx - 1] = needed[idx] = true;
  }
  for (int seg = 0; seg < N; ++seg) {
    if (touched[seg]) continue;
    const SegmentClass& c = s.fixed[seg];
    const bool fails = c.monotonicity.curvature == Curvature::non_monotone ||
                       (options.mode == Mode::cmr && c.inflection.inflection == Inflection::present);
    const int level = c.monotonicity.curvature == Curvature::non_monotone ? c.monotonicity.depth : c.inflection.depth;
    s.fixed_none = s.fixed_none || fails;
    s.fixed_level0_none = s.fixed_level0_none || (fails && level == 0);
  }

  std::vector<int> entry_of(N, -1);
  for (int seg = 0; seg < N; ++seg) {
    if (!needed[seg]) continue;
    const Segment& g = spline.segments()[seg];
    RegionEntry e;
    e.segment = seg;
    e.part = split > 0 && seg >= split ? 1 : 0;
    e.classify = touched[seg];
    const SegmentWindow<Rational> window = segment_window<Rational>(spline, g);
    e.base_exact = bezier_points(window.knots, window.points, d, window.span, Rational(g.a), Rational(g.b));
    // w: the blossom of the data that is 1 on the group (within the window) and 0 elsewhere.
    const int first = g.span - d + 1;  // the window holds P_first .. P_{first+d}
    std::vector<Rational> indicator(d + 1, Rational(0));
    for (int k : s.group)
      if (k >= first && k <= first + d) indicator[k - first] = 1;
    e.weight_exact = bezier_points(window.knots, indicator, d, window.span, Rational(g.a), Rational(g.b));
    for (int i = 0; i <= d; ++i) {
      // Rounding to nearest: error at most half an ulp, bounded by u |v|.
      const double bx = rounded(e.base_exact[i].x), by = rounded(e.base_exact[i].y);
      const double w = rounded(e.weight_exact[i]);
      e.base.push_back({Bounded(bx, Bounded::kRound * std::fabs(bx) + Bounded::kTiny),
                        Bounded(by, Bounded::kRound * std::fabs(by) + Bounded::kTiny)});
      e.weight.push_back(Bounded(w, Bounded::kRound * std::fabs(w) + Bounded::kTiny));
    }
    e.n_xi = 4 * d - 6;
    e.n_nu = 2 * d - 3;
    if (e.classify) {
      std::vector<Point<Poly3>> P;
      for (int i = 0; i <= d; ++i)
        P.push_back({Poly3(e.base_exact[i].x) + Poly3(e.weight_exact[i]) * Poly3::x(),
                     Poly3(e.base_exact[i].y) + Poly3(e.weight_exact[i]) * Poly3::y()});
      for (const Bernstein<Poly3>& piece : piece_polynomials(lambda_bernstein<Poly3>(P), s.piece_levels))
        for (const Poly3& c : piece) e.xi.push_back(rounded_poly<10>(c));
      for (const Bernstein<Poly3>& piece : piece_polynomials(eta_bernstein<Poly3>(P), s.piece_levels))
        for (const Poly3& c : piece) {
          for (int m = 3; m < kPoly3Terms; ++m) CMR_CHECK(sgn(c.c[m]) == 0);  // eta is affine in (dx, dy)
          e.nu.push_back(rounded_poly<3>(c));
        }
    }
    entry_of[seg] = static_cast<int>(s.entries.size());
    s.entries.push_back(std::move(e));
  }
  for (int j : varying_joints) {
    const int idx = s.joints[j].index;
    s.varying.push_back({j, entry_of[idx - 1], entry_of[idx], split > 0 && idx >= split ? 1 : 0});
  }
  return s;
}

namespace {

// Exact sign of kappa_right - kappa_left from the end legs of the two
// segments' Bezier points (the factor (d-1)/d of kappa cancels). T = Bounded
// may answer kSignUnknown; T = Rational answers exactly (0 for a degenerate leg,
// where curvature is undefined, as curvature_jump_sign does).
template <class T>
int jump_sign(const std::vector<Point<T>>& L, const std::vector<Point<T>>& R) {
  const int d = static_cast<int>(L.size()) - 1;
  const Point<T> la = L[d - 1] - L[d], lb = L[d - 2] - L[d - 1];
  const Point<T> ra = R[1] - R[0], rb = R[2] - R[1];
  const T AL = T(0) - det(la, lb), GL = dot(la, la), AR = det(ra, rb), GR = dot(ra, ra);
  const int gl = Scalar<T>::sign(GL), gr = Scalar<T>::sign(GR);
  if (gl == kSignUnknown || gr == kSignUnknown) return kSignUnknown;
  if (gl == 0 || gr == 0) return 0;
  const int sx = Scalar<T>::sign(AR), sy = Scalar<T>::sign(AL);
  if (sx == kSignUnknown || sy == kSignUnknown) return kSignUnknown;
  if (sx != sy) return sx > sy ? 1 : -1;
  if (sx == 0) return 0;
  const T diff = AR * AR * GL * GL * GL - AL * AL * GR * GR * GR;
  const int c = Scalar<T>::sign(diff);
  if (c == kSignUnknown) return kSignUnknown;
  return sx > 0 ? c : -c;
}

PixelResult verdict(const RegionSetup& s, const std::vector<SegmentClass>& classes, const std::vector<Joint>& joints,
                    bool exact) {
  const int N = static_cast<int>(classes.size());
  PixelResult r;
  r.exact = exact;
  const RegionOptions& o = s.options;
  if (o.split) {
    r.label = label_of(combine_split(part_verdict(classes, joints, 0, *o.split, o.mode),
                                     part_verdict(classes, joints, *o.split, N, o.mode)));
  } else {
    r.label = label_of(part_verdict(classes, joints, 0, N, o.mode));
  }
  int depth = 0;
  for (const SegmentClass& c : classes) {
    depth = std::max(depth, c.monotonicity.depth);
    if (o.mode == Mode::cmr) depth = std::max(depth, c.inflection.depth);
  }
  r.depth = static_cast<uint8_t>(depth);
  return r;
}

// Polynomial in (dx, dy) with its certified error bound.
// A closed interval of reals.
struct Interval {
  double lo, hi;
  double mag() const { return std::max(std::fabs(lo), std::fabs(hi)); }
};

// The monomials of poly3.hpp at the displacement of one pixel (a point), or
// over the displacements of a block of pixels (a box c + [-r, r]).
//
// Point: P = sum c_m mu_m is evaluated directly; its error is at most
// kPolyErrorUnits u sum |c_m| |mu_m| (see region.hpp for the count).
// Box: P is expanded around the centre, P(c + h) = sum_st D_st h_x^s h_y^t
// with Taylor coefficients D_st = sum_m c_m T[st][m],
// T[st][m] = C(a_m, s) C(b_m, t) c_x^(a_m - s) c_y^(b_m - t); then over the box
//     |P - D_00| <= sum_{st != 00} |D_st| r_x^s r_y^t,
// and each D_st carries its rounding, kPolyErrorUnits u sum |c_m| |T[st][m]|.
// Expanding at the centre avoids the cancellation that makes a term-by-term
// interval bound useless away from the moved point.
struct Monomials {
  // T[st][m] is non-zero only for s <= a_m and t <= b_m: 35 pairs, listed by m.
  static constexpr int kPairs = 35;
  bool point = true;
  double v[kPoly3Terms];                // point: mu_m
  double a[kPoly3Terms];                // point: |mu_m|
  double tv[kPairs], at[kPairs];        // box: T[st][m] and |T[st][m]| of the non-zero pairs
  uint8_t pair_st[kPairs], pair_m[kPairs];
  double rpow[kPoly3Terms];             // box: r_x^s r_y^t, rounded up
  Monomials(double dx, double dy) {
    const double x2 = dx * dx, xy = dx * dy, y2 = dy * dy;
    const double m[kPoly3Terms] = {1, dx, dy, x2, xy, y2, x2 * dx, x2 * dy, y2 * dx, y2 * dy};
    for (int i = 0; i < kPoly3Terms; ++i) {
      v[i] = m[i];
      a[i] = std::fabs(m[i]);
    }
  }
  Monomials(double cx, double cy, double rx, double ry) : point(false) {
    const double px[4] = {1, cx, cx * cx, cx * cx * cx}, py[4] = {1, cy, cy * cy, cy * cy * cy};
    const double binom[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
    int n = 0;
    for (int m = 0; m < kPoly3Terms; ++m) {
      const int am = kPoly3ExpX[m], bm = kPoly3ExpY[m];
      for (int st = 0; st < kPoly3Terms; ++st) {
        const int s = kPoly3ExpX[st], t = kPoly3ExpY[st];
        if (s > am || t > bm) continue;
        tv[n] = binom[am][s] * binom[bm][t] * px[am - s] * py[bm - t];
        at[n] = std::fabs(tv[n]);
        pair_st[n] = static_cast<uint8_t>(st);
        pair_m[n] = static_cast<uint8_t>(m);
        ++n;
      }
    }
    for (int st = 0; st < kPoly3Terms; ++st) {
      const int s = kPoly3ExpX[st], t = kPoly3ExpY[st];
      const double up = 1 + 8 * Bounded::kRound;
      double r = 1;
      for (int k = 0; k < s; ++k) r *= rx * up;
      for (int k = 0; k < t; ++k) r *= ry * up;
      rpow[st] = r;
    }
  }
};

template <std::size_t K>
Bounded eval_poly(const std::array<double, K>& c, const Monomials& m) {
  // prepare_region guarantees that only an exactly zero polynomial rounds to
  // all zeros: structural zeros (the same for every position) stay exact.
  bool zero = true;
  for (std::size_t i = 0; i < K; ++i) zero = zero && c[i] == 0;
  if (zero) return {0.0, 0.0};
  const double units = kPolyErrorUnits * 0.5 * Bounded::kRound;
  if (m.point) {
    double val = 0, mag = 0;
    for (std::size_t i = 0; i < K; ++i) {
      val += c[i] * m.v[i];
      mag += std::fabs(c[i]) * m.a[i];
    }
    return {val, units * mag + 16 * Bounded::kTiny};
  }
  double d[kPoly3Terms] = {}, mag[kPoly3Terms] = {};
  // Pairs are listed by m, and only m < K carry coefficients (K = 3: 5 pairs).
  constexpr int pairs = K == kPoly3Terms ? Monomials::kPairs : 5;
  static_assert(K == kPoly3Terms || K == 3, "polynomials of degree 3 or 1");
  for (int k = 0; k < pairs; ++k) {
    const double cm = c[m.pair_m[k]];
    d[m.pair_st[k]] += cm * m.tv[k];
    mag[m.pair_st[k]] += std::fabs(cm) * m.at[k];
  }
  double err = units * mag[0] + 16 * Bounded::kTiny;
  for (std::size_t st = 1; st < K; ++st) err += (std::fabs(d[st]) + units * mag[st]) * m.rpow[st] * (1 + 4 * Bounded::kRound);
  return {d[0], err};
}

// Depth-first Algorithms 1 and 2 on the piece polynomials of one entry:
// the same pieces in the same order as algorithm1/algorithm2, and the same
// decisions (each certified), but a piece's coefficients are evaluated only
// as far as its decision needs: the two ends, then the rest until both signs
// have appeared. Pieces below piece_levels are halved from their ancestor.

class LazyPieces {
 public:
  LazyPieces(const RegionEntry& e, const Monomials& m, int levels, bool eta)
      : e_(e), m_(m), levels_(levels), eta_(eta), n1_(eta ? e.n_nu : e.n_xi) {}
  int size() const { return n1_; }

  // Prepares piece (level, j); coefficients then come from coeff(k).
  void select(int level, int j) {
    level_ = level;
    if (level <= levels_) {
      piece_ = (1 << level) - 1 + j;
      return;
    }
    // Halve from the ancestor at the deepest precomputed level.
    const int up = level - levels_;
    piece_ = (1 << levels_) - 1 + (j >> up);
    cur_.resize(n1_);
    for (int k = 0; k < n1_; ++k) cur_[k] = from_poly(k);
    for (int b = up - 1; b >= 0; --b) {
      if ((j >> b) & 1) {
        for (int r = 1; r < n1_; ++r)
          for (int i = 0; i + r < n1_; ++i) cur_[i] = (cur_[i] + cur_[i + 1]).half();
      } else {
        for (int r = 1; r < n1_; ++r)
          for (int i = n1_ - 1; i >= r; --i) cur_[i] = (cur_[i - 1] + cur_[i]).half();
      }
    }
  }
  Bounded coeff(int k) const { return level_ <= levels_ ? from_poly(k) : cur_[k]; }

 private:
  Bounded from_poly(int k) const {
    const std::size_t at = static_cast<std::size_t>(piece_) * n1_ + k;
    return eta_ ? eval_poly(e_.nu[at], m_) : eval_poly(e_.xi[at], m_);
  }
  const RegionEntry& e_;
  const Monomials& m_;
  int levels_;
  bool eta_;
  int n1_;
  int level_ = 0, piece_ = 0;
  std::vector<Bounded> cur_;
};

struct SignScan {
  int pos = 0, neg = 0, zero = 0, unknown = 0, first = 0, last = 0;
  void add(int g) {
    if (g == kSignUnknown) ++unknown;
    else if (g > 0) ++pos;
    else if (g < 0) ++neg;
    else ++zero;
  }
};

// Ends first, then the inner coefficients until both signs are seen.
SignScan scan(const LazyPieces& src) {
  const int n1 = src.size();
  SignScan s;
  s.first = certain_sign(src.coeff(0));
  s.last = n1 > 1 ? certain_sign(src.coeff(n1 - 1)) : s.first;
  s.add(s.first);
  if (n1 > 1) s.add(s.last);
  for (int k = 1; k + 1 < n1 && !(s.pos > 0 && s.neg > 0); ++k) s.add(certain_sign(src.coeff(k)));
  return s;
}

// As monotonicity_piece in classify.cpp (no certain zeros with bounds).
Piece monotonicity_piece(const LazyPieces& src) {
  const SignScan s = scan(src);
  const bool ends_known = s.first != kSignUnknown && s.last != kSignUnknown;
  if (ends_known && s.first * s.last < 0) return Piece::non_monotone;
  if (s.pos > 0 && s.neg > 0) return ends_known ? Piece::split : Piece::uncertain;
  const bool ge = s.neg == 0 && s.unknown == 0, le = s.pos == 0 && s.unknown == 0;
  if (ge && le) return Piece::zero;
  if (ge) return Piece::increasing;
  if (le) return Piece::decreasing;
  return Piece::uncertain;
}

// As inflection_piece in classify.cpp.
Piece inflection_piece(const LazyPieces& src) {
  const SignScan s = scan(src);
  if (s.first == kSignUnknown || s.last == kSignUnknown) return Piece::uncertain;
  if (s.first * s.last <= 0) return Piece::inflection;  // rule (1): nu_0 nu_last <= 0
  if (s.pos == src.size() || s.neg == src.size()) return Piece::no_inflection;
  if (s.neg + s.zero > 0 && s.pos + s.zero > 0) return Piece::split;
  return Piece::uncertain;
}

// Visits pieces depth first; `visit(piece, level)` folds an outcome and
// returns true to stop. Returns false when a decision was uncertain.
template <class Decide, class Visit>
bool traverse_pieces(LazyPieces& src, int max_depth, Decide decide, Visit visit) {
  std::vector<std::pair<int, int>> stack{{0, 0}};
  while (!stack.empty()) {
    const auto [level, j] = stack.back();
    stack.pop_back();
    src.select(level, j);
    const Piece p = decide(src);
    if (p == Piece::uncertain) return false;
    if (p == Piece::split && level < max_depth) {
      stack.push_back({level + 1, 2 * j + 1});
      stack.push_back({level + 1, 2 * j});
      continue;
    }
    if (visit(p, level)) break;
  }
  return true;
}

std::optional<MonotonicityResult> lazy_algorithm1(const RegionEntry& e, const Monomials& m, int levels, int D) {
  LazyPieces src(e, m, levels, false);
  MonotonicityFold fold;
  if (!traverse_pieces(src, D, monotonicity_piece, [&](Piece p, int level) { return fold.visit(p, level); }))
    return std::nullopt;
  return fold.result(D);
}

std::optional<InflectionResult> lazy_algorithm2(const RegionEntry& e, const Monomials& m, int levels, int D) {
  LazyPieces src(e, m, levels, true);
  src.select(0, 0);
  const int kappa_sign = certain_sign(src.coeff(0));
  InflectionFold fold;
  if (!traverse_pieces(src, D, inflection_piece, [&](Piece p, int level) { return fold.visit(p, level); }))
    return std::nullopt;
  return fold.result(D, kappa_sign);
}

}  // namespace

PixelResult classify_position_exact(const RegionSetup& s, Vec2 p) {
  if (s.fixed_level0_none) return {0, 0, false};
  const Rational dx = Rational(p.x) - Rational(s.anchor.x), dy = Rational(p.y) - Rational(s.anchor.y);
  const RegionOptions& o = s.options;
  std::vector<std::vector<Point<Rational>>> B(s.entries.size());
  std::vector<Bernstein<Rational>> xi(s.entries.size()), nu(s.entries.size());
  for (std::size_t e = 0; e < s.entries.size(); ++e) {
    const RegionEntry& en = s.entries[e];
    for (std::size_t i = 0; i < en.base_exact.size(); ++i)
      B[e].push_back({en.base_exact[i].x + en.weight_exact[i] * dx, en.base_exact[i].y + en.weight_exact[i] * dy});
    if (!en.classify) continue;
    xi[e] = lambda_bernstein<Rational>(B[e]);
    if (sgn(xi[e].front()) * sgn(xi[e].back()) < 0) return {0, 0, true};
    if (o.mode == Mode::cmr) {
      nu[e] = eta_bernstein<Rational>(B[e]);
      if (sgn(nu[e].front()) * sgn(nu[e].back()) <= 0) return {0, 0, true};
    }
  }
  std::vector<SegmentClass> classes = s.fixed;
  for (std::size_t e = 0; e < s.entries.size(); ++e) {
    if (!s.entries[e].classify) continue;
    SegmentClass c;
    c.monotonicity = *algorithm1(xi[e], o.max_depth);
    if (o.mode == Mode::cmr) c.inflection = *algorithm2(nu[e], o.max_depth);
    c.exact_used = true;
    classes[s.entries[e].segment] = c;
  }
  std::vector<Joint> joints = s.joints;
  for (const RegionJoint& j : s.varying) joints[j.joint].jump = jump_sign<Rational>(B[j.left], B[j.right]);
  return verdict(s, classes, joints, true);
}

namespace {

// The curvature jumps of the joints whose jump depends on the position, for
// displacements enclosed by (bx, by): B = B0 + w d. False when a sign is not
// certain there.
bool varying_jumps(const RegionSetup& s, Bounded bx, Bounded by, std::vector<Joint>& joints) {
  if (s.varying.empty()) return true;
  std::vector<std::vector<Point<Bounded>>> B(s.entries.size());
  for (std::size_t e = 0; e < s.entries.size(); ++e)
    for (std::size_t i = 0; i < s.entries[e].base.size(); ++i)
      B[e].push_back({s.entries[e].base[i].x + s.entries[e].weight[i] * bx,
                      s.entries[e].base[i].y + s.entries[e].weight[i] * by});
  for (const RegionJoint& j : s.varying) {
    const int sign = jump_sign<Bounded>(B[j.left], B[j.right]);
    if (sign == kSignUnknown) return false;
    joints[j.joint].jump = sign;
  }
  return true;
}

// The certified fast path for a point or a box of displacements: the result
// holds for every displacement in the box, or nullopt when some deciding sign
// is not certain there (then split the box, or for a point go exact).
// bx, by enclose the displacements for the joint computations.
std::optional<PixelResult> classify_fast(const RegionSetup& s, const Monomials& mono, Bounded bx, Bounded by) {
  if (s.fixed_level0_none) return PixelResult{0, 0, false};
  const RegionOptions& o = s.options;
  // Level 0 first: any segment whose end coefficients prove non-monotonicity
  // (or, for CMR, an inflection) decides the pixel.
  bool uncertain = false;
  for (const RegionEntry& e : s.entries) {
    if (!e.classify) continue;
    const int a = certain_sign(eval_poly(e.xi[0], mono)), b = certain_sign(eval_poly(e.xi[e.n_xi - 1], mono));
    if (a != kSignUnknown && b != kSignUnknown && a * b < 0) return PixelResult{0, 0, false};
    uncertain = uncertain || a == kSignUnknown || b == kSignUnknown;
    if (o.mode == Mode::cmr) {
      const int c = certain_sign(eval_poly(e.nu[0], mono)), f = certain_sign(eval_poly(e.nu[e.n_nu - 1], mono));
      if (c != kSignUnknown && f != kSignUnknown && c * f <= 0) return PixelResult{0, 0, false};
      uncertain = uncertain || c == kSignUnknown || f == kSignUnknown;
    }
  }
  if (uncertain) return std::nullopt;
  std::vector<SegmentClass> classes = s.fixed;
  for (const RegionEntry& e : s.entries) {
    if (!e.classify) continue;
    const auto m = lazy_algorithm1(e, mono, s.piece_levels, o.max_depth);
    if (!m) return std::nullopt;
    SegmentClass c;
    c.monotonicity = *m;
    if (o.mode == Mode::cmr) {
      const auto i = lazy_algorithm2(e, mono, s.piece_levels, o.max_depth);
      if (!i) return std::nullopt;
      c.inflection = *i;
    }
    classes[e.segment] = c;
  }
  std::vector<Joint> joints = s.joints;
  if (!varying_jumps(s, bx, by, joints)) return std::nullopt;
  return verdict(s, classes, joints, false);
}

// Labels for a whole box of displacements without following each pixel's
// traversal (used only when no depth map is wanted, since decision levels
// may differ between the pixels). Per touched segment, a depth-first search
// over pieces (levels <= D) where a piece whose coefficients are certainly
// all >= 0 (or <= 0) over the box is a leaf in that direction, one whose end
// coefficients certainly differ in sign proves "not monotone", and any other
// piece is split even when some pixels would decide it: the sub-pieces of a
// piece that is monotone for a pixel are monotone the same way. For every
// pixel of the box Algorithm 1 then gives the same direction, or "not
// monotone": no ancestor of a piece with opposite end signs can be decided
// increasing or decreasing, and undecided pieces do not stop the traversal.
// Algorithm 2 likewise (all coefficients strictly one sign: no inflection;
// opposite end signs: an inflection). nullopt when a piece at level D stays
// unresolved over the box.
enum class BoxOutcome { increasing, decreasing, not_monotone, unresolved };
constexpr int kBoxPieceBudget = 6;

BoxOutcome box_traversal(const RegionEntry& e, const Monomials& mono, int levels, int D, bool eta, int* kappa) {
  LazyPieces src(e, mono, levels, eta);
  bool inc = false, dec = false;
  int level = 0, j = 0;
  // A box that needs many pieces is cheaper to quarter than to resolve.
  for (int visited = 0;; ++visited) {
    if (visited == kBoxPieceBudget) return BoxOutcome::unresolved;
    src.select(level, j);
    const int n1 = src.size();
    const int first = certain_sign(src.coeff(0)), last = certain_sign(src.coeff(n1 - 1));
    // Opposite ends prove non-monotonicity; for eta a zero end is already an
    // inflection (rule (1) of Algorithm 2).
    if (first != kSignUnknown && last != kSignUnknown && (eta ? first * last <= 0 : first * last < 0))
      return BoxOutcome::not_monotone;
    int pos = 0, neg = 0, zero = 0, unknown = 0;
    for (int k = 0; k < n1 && unknown == 0 && !(pos && neg); ++k) {
      const int g = certain_sign(src.coeff(k));
      if (g == kSignUnknown) ++unknown;
      else if (g == 0) ++zero;
      else (g > 0 ? pos : neg)++;
    }
    if (zero == n1) return BoxOutcome::unresolved;  // lambda == 0 (a straight segment): leave it to the pixels
    // A leaf: for lambda every coefficient >= 0 (or <= 0), rules (1)/(2) of
    // Algorithm 1; for eta every coefficient strictly one sign.
    const bool leaf_up = unknown == 0 && neg == 0 && (!eta || zero == 0);
    const bool leaf_down = unknown == 0 && pos == 0 && (!eta || zero == 0);
    if (!leaf_up && !leaf_down) {
      if (level >= D) return BoxOutcome::unresolved;
      ++level;
      j *= 2;
      continue;
    }
    inc = inc || leaf_up;
    dec = dec || leaf_down;
    if (inc && dec) return BoxOutcome::not_monotone;
    while (level > 0 && (j & 1) == 1) {
      --level;
      j >>= 1;
    }
    if (level == 0) break;
    ++j;
  }
  if (kappa) *kappa = inc ? 1 : -1;
  return inc ? BoxOutcome::increasing : BoxOutcome::decreasing;
}

std::optional<PixelResult> classify_box_labels(const RegionSetup& s, const Monomials& mono, Bounded bx, Bounded by) {
  if (s.fixed_none) return PixelResult{0, 0, false};  // that segment's part is "none" for every position
  const RegionOptions& o = s.options;
  const int D = o.max_depth;
  // The cheapest proof first: a whole segment with opposite end signs.
  for (const RegionEntry& e : s.entries) {
    if (!e.classify) continue;
    const int a = certain_sign(eval_poly(e.xi[0], mono)), b = certain_sign(eval_poly(e.xi[e.n_xi - 1], mono));
    if (a != kSignUnknown && b != kSignUnknown && a * b < 0) return PixelResult{0, 0, false};
  }
  std::vector<SegmentClass> classes = s.fixed;
  for (const RegionEntry& e : s.entries) {
    if (!e.classify) continue;
    SegmentClass c;
    switch (box_traversal(e, mono, s.piece_levels, D, false, nullptr)) {
      case BoxOutcome::not_monotone: return PixelResult{0, 0, false};
      case BoxOutcome::unresolved: return std::nullopt;  // smaller blocks will do
      case BoxOutcome::increasing: c.monotonicity = {Curvature::increasing, 0}; break;
      case BoxOutcome::decreasing: c.monotonicity = {Curvature::decreasing, 0}; break;
    }
    if (o.mode == Mode::cmr) {
      // For eta, "increasing" means all pieces positive: no inflection, kappa > 0.
      int kappa = 0;
      switch (box_traversal(e, mono, s.piece_levels, D, true, &kappa)) {
        case BoxOutcome::not_monotone: return PixelResult{0, 0, false};  // an inflection
        case BoxOutcome::unresolved: return std::nullopt;
        default: c.inflection = {Inflection::none, 0, kappa}; break;
      }
    }
    classes[e.segment] = c;
  }
  std::vector<Joint> joints = s.joints;
  if (!varying_jumps(s, bx, by, joints)) return std::nullopt;
  PixelResult r = verdict(s, classes, joints, false);
  r.depth = 0;
  return r;
}

// The displacements of pixel columns i0..i1 (inclusive), enclosing the exact
// values: the ends are rounded once, so widen them by a relative u.
Interval displacement_range(double first, double last, double anchor) {
  const double lo = first - anchor, hi = last - anchor;
  return {lo - 0.5 * Bounded::kRound * std::fabs(lo), hi + 0.5 * Bounded::kRound * std::fabs(hi)};
}

}  // namespace

PixelResult classify_position(const RegionSetup& s, Vec2 p) {
  // dx = fl(p - P_k): one rounding, relative to |dx|, covered by kPolyErrorUnits.
  const double dx = p.x - s.anchor.x, dy = p.y - s.anchor.y;
  const Bounded bx(dx, 0.5 * Bounded::kRound * std::fabs(dx)), by(dy, 0.5 * Bounded::kRound * std::fabs(dy));
  if (const auto r = classify_fast(s, Monomials(dx, dy), bx, by)) return *r;
  return classify_position_exact(s, p);
}

std::optional<PixelResult> classify_block(const RegionSetup& s, int i0, int j0, int i1, int j1) {
  const RegionOptions& o = s.options;
  const View& v = *o.view;
  // Columns run left to right (x grows with i), rows top to bottom (y falls with j).
  const Interval x = displacement_range(pixel_center(v, o.width, o.height, i0, 0).x,
                                        pixel_center(v, o.width, o.height, i1, 0).x, s.anchor.x);
  const Interval y = displacement_range(pixel_center(v, o.width, o.height, 0, j1).y,
                                        pixel_center(v, o.width, o.height, 0, j0).y, s.anchor.y);
  // Centre and half-width enclosing [lo, hi] despite their rounding.
  const Bounded bx(0.5 * x.lo + 0.5 * x.hi, 0.5 * x.hi - 0.5 * x.lo + Bounded::kRound * x.mag());
  const Bounded by(0.5 * y.lo + 0.5 * y.hi, 0.5 * y.hi - 0.5 * y.lo + Bounded::kRound * y.mag());
  const Monomials mono(bx.v, by.v, bx.e, by.e);
  if (!o.depth) return classify_box_labels(s, mono, bx, by);
  return classify_fast(s, mono, bx, by);
}

RegionImage blank_image(const RegionSetup& s) {
  const RegionOptions& o = s.options;
  RegionImage img;
  img.width = o.width;
  img.height = o.height;
  img.view = *o.view;
  img.labels.assign(static_cast<std::size_t>(o.width) * o.height, 0);
  img.depth.assign(img.labels.size(), 0);
  return img;
}

constexpr int kPixelsPerSmallBlock = 4;

std::vector<std::array<int, 2>> region_cull(const RegionSetup& s, RegionImage& img, int min_block, int threads) {
  const RegionOptions& o = s.options;
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (!o.depth && s.fixed_none) return {};  // every label is 0 (img is all zero)
  // Blocks of kRegionBlock pixels are decided whole when the certified path
  // holds over all their displacements, else quartered; blocks no larger than
  // min_block are listed for the caller (single pixels with min_block == 1
  // are decided here through classify_position).
  const int bw = (o.width + kRegionBlock - 1) / kRegionBlock, bh = (o.height + kRegionBlock - 1) / kRegionBlock;
  std::atomic<int> next{0};
  std::atomic<std::uint64_t> exact{0};
  std::vector<std::vector<std::array<int, 2>>> listed(bw * bh);
  auto fill = [&](int i0, int j0, int i1, int j1, const PixelResult& r) {
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const std::size_t at = static_cast<std::size_t>(j) * o.width + i;
        img.labels[at] = r.label;
        img.depth[at] = r.depth;
      }
  };
  auto work = [&] {
    std::uint64_t local_exact = 0;
    std::vector<std::array<int, 4>> todo;
    for (int b = next++; b < bw * bh; b = next++) {
      const int bi = b % bw, bj = b / bw;
      todo.push_back({bi * kRegionBlock, bj * kRegionBlock, std::min(o.width, (bi + 1) * kRegionBlock) - 1,
                      std::min(o.height, (bj + 1) * kRegionBlock) - 1});
      while (!todo.empty()) {
        const auto [i0, j0, i1, j1] = todo.back();
        todo.pop_back();
        // Blocks of a few pixels: evaluating the pixels (here, or on the
        // device when min_block > 1) is cheaper than a box.
        if ((i1 - i0 + 1) * (j1 - j0 + 1) <= kPixelsPerSmallBlock) {
          for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
              if (min_block > 1) {
                listed[b].push_back({i, j});
                continue;
              }
              const PixelResult r = classify_position(s, pixel_center(img.view, o.width, o.height, i, j));
              fill(i, j, i, j, r);
              local_exact += r.exact;
            }
          continue;
        }
        if (const auto r = classify_block(s, i0, j0, i1, j1)) {
          fill(i0, j0, i1, j1, *r);
          continue;
        }
        if (i1 - i0 < min_block && j1 - j0 < min_block) {
          for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) listed[b].push_back({i, j});
          continue;
        }
        const int im = (i0 + i1) / 2, jm = (j0 + j1) / 2;
        todo.push_back({i0, j0, im, jm});
        if (im < i1) todo.push_back({im + 1, j0, i1, jm});
        if (jm < j1) todo.push_back({i0, jm + 1, im, j1});
        if (im < i1 && jm < j1) todo.push_back({im + 1, jm + 1, i1, j1});
      }
    }
    exact += local_exact;
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  img.exact_pixels += exact;
  if (!o.depth) std::fill(img.depth.begin(), img.depth.end(), 0);
  std::vector<std::array<int, 2>> out;
  for (const auto& l : listed) out.insert(out.end(), l.begin(), l.end());
  return out;
}

RegionImage region_cpu(const RegionSetup& s, int threads) {
  RegionImage img = blank_image(s);
  region_cull(s, img, 1, threads);
  return img;
}

}  // namespace cmr::detail
