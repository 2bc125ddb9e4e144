#include "region/region_setup.hpp"

#include "bezierize/algorithms.hpp"
#include "region/box_eval.hpp"
#include "region/box_reuse.hpp"
#include "bezierize/decide.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <span>

#include "numeric/halve_bounded.hpp"
#include "numeric/halve_pairs.hpp"
#include "bezierize/lambda.hpp"
#include "region/pixel_simd.hpp"
#include "numeric/poly3.hpp"
#include "bezierize/rational_lambda.hpp"
#include "region/region_pieces.hpp"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"

namespace cmr::backend {

namespace {

double rounded(const Rational& q) { return q.get_d(); }

// q 2^-e, exactly.
Rational scaled(Rational q, int e) {
  if (e > 0) mpq_div_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(e));
  if (e < 0) mpq_mul_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(-e));
  return q;
}

// The point group: k first, then the rigid members without repeats. On a
// closed spline every member brings its twin in the unrolled form (the same
// control point), so the curve stays closed.
std::vector<int> point_group(const BSpline& spline, const RegionRequest& o) {
  std::vector<int> group{o.point};
  for (int g : o.with)
    if (std::find(group.begin(), group.end(), g) == group.end()) group.push_back(g);
  for (std::size_t i = 0, n = group.size(); i < n; ++i)
    if (const int t = spline.twin(group[i]); t >= 0 && std::find(group.begin(), group.end(), t) == group.end())
      group.push_back(t);
  return group;
}

// Judged segments the move changes (touched) and those the setup needs
// (touched, or next to a joint whose curvature jump varies: non-C2, strictly
// inside the judged range, not a cut joint, next to a touched segment); the
// varying joints go to `varying`. Segments outside the range are ignored.
void find_needed(const RegionSetup& s, std::vector<bool>& touched, std::vector<bool>& needed,
                 std::vector<int>& varying) {
  const int N = s.spline().segment_count();
  touched.assign(N, false);
  needed.assign(N, false);
  for (const SegmentInfluence& si : influence(s.spline(), s.group))
    if (si.segment >= s.range.first && si.segment <= s.range.last) touched[si.segment] = needed[si.segment] = true;
  const std::vector<Joint>& joints = s.joints();
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const int idx = joints[j].index;
    if (!joint_counts(s.range, s.cuts, idx) || joints[j].continuity >= 2) continue;  // cut joint: free; C2: no jump
    if (!touched[idx - 1] && !touched[idx]) continue;
    varying.push_back(static_cast<int>(j));
    needed[idx - 1] = needed[idx] = true;
  }
  if (s.around && s.seam().continuity < 2 && (touched[N - 1] || touched[0])) {
    varying.push_back(static_cast<int>(joints.size()));  // the seam
    needed[N - 1] = needed[0] = true;
  }
}

// fixed_none / fixed_level0_none: an untouched judged segment fails for every
// position, and so does a judged segment with a pole (touched or not: the
// move keeps the weights, so W and its roots do not depend on the position;
// analyze gives such a segment pole_class()).
void mark_fixed_failures(RegionSetup& s, const std::vector<bool>& touched) {
  for (int seg = s.range.first; seg <= s.range.last; ++seg) {
    if (s.base->analysis.shapes[seg].pole) s.fixed_none = s.fixed_level0_none = true;
    if (touched[seg]) continue;
    const SegmentClass& c = s.fixed()[seg];
    const bool fails = c.monotonicity.curvature == Curvature::non_monotone ||
                       (s.options.mode == Mode::cmr && c.inflection.inflection == Inflection::present);
    const int level = c.monotonicity.curvature == Curvature::non_monotone ? c.monotonicity.depth : c.inflection.depth;
    s.fixed_none = s.fixed_none || fails;
    s.fixed_level0_none = s.fixed_level0_none || (fails && level == 0);
  }
}

// B0 (scaled by 2^-scale_exponent) and w of segment g exactly (w: the blossom of the data that is 1 on the
// group within the window and 0 elsewhere), and both rounded with bounds.
void set_moved_points(const RegionSetup& s, const Segment& g, RegionEntry& e) {
  const int d = s.spline().degree();
  const SegmentWindow<Rational> window = segment_window<Rational>(s.spline(), g);
  const int first = g.span - d + 1;  // the window holds P_first .. P_{first+d}
  // A Bezier window's control values are its Bezier values exactly
  // (extract.hpp, bezier_window): the rational blossoms, O(d^3) GMP steps, are skipped.
  const bool bezier = bezier_window(s.spline(), g);
  const auto bezier_values = [&](const auto& values) {
    return bezier ? values : bezier_points(window.knots, values, d, window.span, Rational(g.a), Rational(g.b));
  };
  std::vector<Rational> indicator(d + 1, Rational(0));
  for (int k : s.group)
    if (k >= first && k <= first + d) indicator[k - first] = Rational(s.spline().weight(k));  // (w x) moves by w d
  e.weight_exact = bezier_values(indicator);
  if (s.spline().is_rational()) {
    for (const HPoint<Rational>& h : bezier_values(homogeneous_window_points<Rational>(s.spline(), g))) {
      e.base_exact.push_back({h.x, h.y});
      e.hw_exact.push_back(h.z);
      const double w = rounded(h.z);
      e.hw.push_back(Bounded(w, Bounded::kRound * std::fabs(w) + Bounded::kTiny));
    }
  } else {
    e.base_exact = bezier_values(window.points);
  }
  if (s.scale_exponent != 0)  // the kernel's problem (RegionSetup::scale_exponent); weights are not lengths
    for (Point<Rational>& b : e.base_exact) b = {scaled(b.x, s.scale_exponent), scaled(b.y, s.scale_exponent)};
  for (int i = 0; i <= d; ++i) {
    // Rounding to nearest: error at most half an ulp, bounded by u |v|.
    const double bx = rounded(e.base_exact[i].x), by = rounded(e.base_exact[i].y);
    const double w = rounded(e.weight_exact[i]);
    e.base.push_back({Bounded(bx, Bounded::kRound * std::fabs(bx) + Bounded::kTiny),
                      Bounded(by, Bounded::kRound * std::fabs(by) + Bounded::kTiny)});
    e.weight.push_back(Bounded(w, Bounded::kRound * std::fabs(w) + Bounded::kTiny));
  }
}

// The rounded piece polynomials xi_k(dx, dy) and nu_k(dx, dy) of a touched
// entry, formed and halved in integers over common denominators
// (region_pieces.hpp): the values of halving the exact Poly3 coefficients,
// without a gcd per operation.
void set_piece_polynomials(RegionEntry& e, int piece_levels) {
  if (e.hw_exact.empty() && e.base_exact.size() >= 3) {
    MovedPieces pieces = moved_pieces(e.base_exact, e.weight_exact, piece_levels);
    e.xi = std::move(pieces.xi);
    e.nu = std::move(pieces.nu);
    return;
  }
  std::vector<Point<Poly3>> P;
  std::vector<HPoint<Poly3>> H;
  for (std::size_t i = 0; i < e.base_exact.size(); ++i) {
    P.push_back({Poly3(e.base_exact[i].x) + Poly3(e.weight_exact[i]) * Poly3::x(),
                 Poly3(e.base_exact[i].y) + Poly3(e.weight_exact[i]) * Poly3::y()});
    if (!e.hw_exact.empty()) H.push_back({P.back().x, P.back().y, Poly3(e.hw_exact[i])});
  }
  const bool rational = !e.hw_exact.empty();
  e.xi = rounded_pieces<10>(rational ? rational_lambda_bernstein<Poly3>(H) : lambda_bernstein<Poly3>(P), piece_levels);
  e.nu = rounded_pieces<3>(rational ? rational_d_bernstein<Poly3>(H) : eta_bernstein<Poly3>(P), piece_levels);
}

}  // namespace

namespace {

// What part_verdict reads of a run of segments [a, b): its flags, the first
// and last curvature sign of the kappa chain (CMR), the jumps of the joints
// inside it, and the deepest levels.
struct RunSummary {
  bool inc = false, dec = false, none = false, undecided = false, up = false, down = false, k_seen = false;
  int k_first = 0, k_last = 0, mono_depth = 0, infl_depth = 0;
};

// Mirrors part_verdict (analyze.cpp) over one run, the chain starting afresh.
RunSummary summarize_run(const std::vector<SegmentClass>& classes, const std::vector<Joint>& joints, int a, int b,
                         Mode mode) {
  RunSummary r;
  for (int i = a; i < b; ++i) {
    const SegmentClass& c = classes[i];
    r.mono_depth = std::max(r.mono_depth, c.monotonicity.depth);
    r.infl_depth = std::max(r.infl_depth, c.inflection.depth);
    switch (c.monotonicity.curvature) {
      case Curvature::increasing: r.inc = true; break;
      case Curvature::decreasing: r.dec = true; break;
      case Curvature::non_monotone: r.none = true; break;
      case Curvature::undecided: r.undecided = true; break;
      case Curvature::constant: break;
    }
    if (mode != Mode::cmr) continue;
    switch (c.inflection.inflection) {
      case Inflection::present: r.none = true; break;
      case Inflection::undecided: r.undecided = true; break;
      case Inflection::none:
        if (c.inflection.kappa_sign == 0) break;  // straight: skipped by the chain, as in part_verdict
        if (!r.k_seen) r.k_first = c.inflection.kappa_sign;
        else if (c.inflection.kappa_sign != r.k_last) r.none = true;
        r.k_seen = true;
        r.k_last = c.inflection.kappa_sign;
        break;
    }
  }
  for (int i = a + 1; i < b; ++i) {
    r.up = r.up || joints[i - 1].jump > 0;
    r.down = r.down || joints[i - 1].jump < 0;
  }
  return r;
}

SegmentClass stand_in(Curvature curvature, Inflection inflection, int kappa_sign) {
  SegmentClass c;
  c.monotonicity.curvature = curvature;
  c.inflection.inflection = inflection;
  c.inflection.kappa_sign = kappa_sign;
  return c;
}

// The stand-ins of one run: one non-monotone class when the run alone makes
// its part "none"; otherwise its direction (carrying the first curvature
// sign), the last curvature sign when it differs (a chain 0..0 c..c), an
// undecided class when the run has one, and a neutral class when a jump needs
// a joint to sit on. Each keeps part_verdict's flags and chain unchanged.
std::vector<SegmentClass> stand_ins(const RunSummary& r, int& jump) {
  jump = 0;
  std::vector<SegmentClass> out;
  if (r.none || (r.inc && r.dec) || (r.up && r.down)) {
    out.push_back(stand_in(Curvature::non_monotone, Inflection::undecided, 0));
  } else {
    // Without a chain value (CMR: the run's inflections were undecided or its
    // segments straight) the stand-ins carry sign 0, which part_verdict skips;
    // an undecided inflection is kept by the undecided stand-in below. In
    // CMRWI the inflection is not read.
    const auto tail = [&](Curvature c) { return stand_in(c, Inflection::none, r.k_seen ? r.k_last : 0); };
    const Curvature dir = r.inc ? Curvature::increasing : (r.dec ? Curvature::decreasing : Curvature::constant);
    out.push_back(stand_in(dir, Inflection::none, r.k_seen ? r.k_first : 0));
    if (r.k_seen && r.k_last != r.k_first) out.push_back(tail(Curvature::constant));
    if (r.undecided) out.push_back(tail(Curvature::undecided));
    if ((r.up || r.down) && out.size() == 1) out.push_back(tail(Curvature::constant));
    jump = r.up ? 1 : (r.down ? -1 : 0);
  }
  out.front().monotonicity.depth = r.mono_depth;
  out.front().inflection.depth = r.infl_depth;
  return out;
}

}  // namespace

VerdictTemplate fold_fixed_runs(const std::vector<SegmentClass>& classes, const std::vector<Joint>& joints,
                                const std::vector<bool>& needed, SegmentRange range, const std::vector<int>& cuts,
                                Mode mode) {
  const int N = static_cast<int>(classes.size());
  CMR_CHECK(static_cast<int>(needed.size()) == N && static_cast<int>(joints.size()) == N - 1);
  CMR_CHECK(range.first >= 0 && range.first <= range.last && range.last < N);
  const auto is_cut = [&](int seg) { return std::find(cuts.begin(), cuts.end(), seg) != cuts.end(); };
  VerdictTemplate t;
  t.slot.assign(N, -1);
  t.starts.push_back(0);
  // Appends the classes of segments [a, ...) after the real joint that precedes segment a.
  const auto append = [&](int a, const std::vector<SegmentClass>& items, int inner_jump) {
    if (!t.classes.empty()) t.joints.push_back(joints[a - 1]);
    if (a != range.first && is_cut(a)) t.starts.push_back(static_cast<int>(t.classes.size()));
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (i > 0) {
        Joint j;
        j.jump = i == 1 ? inner_jump : 0;
        t.joints.push_back(j);
      }
      t.classes.push_back(items[i]);
    }
  };
  int run = -1;  // first segment of the open run
  const auto flush = [&](int end) {
    if (run < 0) return;
    int jump = 0;
    const std::vector<SegmentClass> items = stand_ins(summarize_run(classes, joints, run, end, mode), jump);
    append(run, items, jump);
    run = -1;
  };
  for (int seg = range.first; seg <= range.last; ++seg) {
    if (needed[seg] || is_cut(seg)) flush(seg);
    if (needed[seg]) {
      t.slot[seg] = static_cast<int>(t.classes.size());
      append(seg, {classes[seg]}, 0);
    } else if (run < 0) {
      run = seg;
    }
  }
  flush(range.last + 1);
  return t;
}

std::vector<Direction> group_verdicts(const VerdictTemplate& t, const std::vector<SegmentClass>& classes,
                                      const std::vector<Joint>& joints, Mode mode) {
  std::vector<Direction> out;
  for (std::size_t g = 0; g < t.starts.size(); ++g) {
    const int end = g + 1 < t.starts.size() ? t.starts[g + 1] : static_cast<int>(classes.size());
    out.push_back(part_verdict(classes, joints, t.starts[g], end, mode));
  }
  return out;
}

int kernel_scale_exponent(const BSpline& spline) {
  double m = 0;
  for (const Vec2& p : spline.points()) m = std::max({m, std::fabs(p.x), std::fabs(p.y)});
  if (m == 0 || !std::isfinite(m) || (m >= 0x1p-64 && m <= 0x1p64)) return 0;
  return std::ilogb(m);
}

std::shared_ptr<const RegionBase> region_base(const BSpline& spline, int max_depth) {
  AnalyzeOptions ao;
  ao.classify.max_depth = max_depth;
  return std::make_shared<const RegionBase>(RegionBase{spline, analyze(spline, ao), max_depth});
}

RegionEntry prepare_entry(const RegionSetup& s, int segment, bool classify) {
  const int d = s.spline().degree();
  RegionEntry e;
  e.segment = segment;
  e.classify = classify;
  set_moved_points(s, s.spline().segments()[segment], e);
  e.n_xi = s.spline().is_rational() ? 8 * d - 11 : 4 * d - 6;
  e.n_nu = s.spline().is_rational() ? 3 * d - 5 : 2 * d - 3;
  if (e.classify) set_piece_polynomials(e, s.piece_levels);
  return e;
}

RegionSetup prepare_region(const BSpline& spline, const RegionRequest& options,
                           std::shared_ptr<const RegionBase> base, const EntrySource& entries) {
  validate_region_options(spline, options);
  if (!base) base = region_base(spline, options.max_depth);
  CMR_CHECK(base->max_depth == options.max_depth && base->spline.point_count() == spline.point_count());
  RegionSetup s{std::move(base), options, {}, {}, {}, {}, {}, {}, {}, false, false, std::min(options.max_depth, kPieceLevels)};
  if (!s.options.view) {
    s.options.view = default_view(spline, options.width, options.height);
    validate_region_options(spline, s.options);  // a default view of huge coordinates can overflow
  }
  s.group = point_group(spline, options);
  s.anchor = spline.points()[options.point];
  s.scale_exponent = kernel_scale_exponent(spline);
  s.scale = std::ldexp(1.0, -s.scale_exponent);
  s.range = judged_range(options.segments, spline.segment_count());
  s.cuts = options.split        ? std::vector<int>{*options.split}
           : options.each_piece ? each_piece_cuts(s.range, options.splits)
                                : options.splits;
  const int N = spline.segment_count();
  s.around = spline.closed() && s.range.first == 0 && s.range.last == N - 1 && s.cuts.empty() && !options.each_piece;

  std::vector<bool> touched, needed;
  std::vector<int> varying_joints;
  find_needed(s, touched, needed, varying_joints);
  mark_fixed_failures(s, touched);
  if (s.around) {
    std::vector<SegmentClass> classes = s.fixed();
    classes.push_back(neutral_class());
    std::vector<Joint> joints = s.joints();
    joints.push_back(s.seam());
    std::vector<bool> with_neutral = needed;
    with_neutral.push_back(false);
    s.verdict = fold_fixed_runs(classes, joints, with_neutral, {0, N}, {}, options.mode);
    s.verdict.slot.pop_back();
  } else {
    s.verdict = fold_fixed_runs(s.fixed(), s.joints(), needed, s.range, s.cuts, options.mode);
  }
  std::vector<int> entry_of(N, -1);
  for (int seg = 0; seg < N; ++seg) {
    if (!needed[seg]) continue;
    RegionEntry e = entries ? entries(s, seg, touched[seg]) : prepare_entry(s, seg, touched[seg]);
    e.part = group_of(s.cuts, seg);
    entry_of[seg] = static_cast<int>(s.entries.size());
    s.entries.push_back(std::move(e));
  }
  for (int j : varying_joints) {
    if (j == static_cast<int>(s.joints().size())) {
      s.varying.push_back({j, entry_of[N - 1], entry_of[0], 0, true});
      continue;
    }
    const int idx = s.joints()[j].index;
    s.varying.push_back({j, entry_of[idx - 1], entry_of[idx], group_of(s.cuts, idx)});
  }
  return s;
}

namespace {

using box_eval::eval_poly;
using box_eval::Monomials;

// A varying joint's index in the verdict template: it sits before its right
// segment, which is an entry and so has a slot of its own.
int verdict_joint(const RegionSetup& s, const RegionJoint& j) {
  // The seam follows segment N-1 (the template's neutral class comes after it).
  if (j.seam) return s.verdict.slot[s.entries[j.left].segment];
  return s.verdict.slot[s.entries[j.right].segment] - 1;
}

// The label from the verdict template with the entries' classes and the
// varying jumps filled in (VerdictTemplate: O(entries), not O(segments)).
PixelResult verdict(const RegionSetup& s, const std::vector<SegmentClass>& classes, const std::vector<Joint>& joints,
                    bool exact) {
  PixelResult r;
  r.exact = exact;
  const RegionRequest& o = s.options;
  if (labels_of(o) == Labels::plain) {  // one group: no vector of verdicts (no heap per pixel)
    const std::vector<int>& starts = s.verdict.starts;
    const int end = starts.size() > 1 ? starts[1] : static_cast<int>(classes.size());
    r.label = code(part_verdict(classes, joints, starts[0], end, o.mode));
  }
  const std::vector<Direction> groups =
      labels_of(o) == Labels::plain ? std::vector<Direction>{} : group_verdicts(s.verdict, classes, joints, o.mode);
  switch (labels_of(o)) {
    case Labels::plain: break;
    case Labels::split: r.label = code(combine_split(groups[0], groups[1])); break;
    case Labels::alternating: r.label = code(alternation_verdict(groups)); break;
    case Labels::each_piece: r.label = code(each_piece_verdict(groups)); break;
  }
  int depth = 0;  // the template holds the judged segments only; stand-ins carry their runs' depths
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


// The region pixel (and block) source of the one traversal (decide.hpp):
// the pieces of one entry's xi (or nu) at one displacement (or over a box of
// them). Pieces down to the precomputed levels come from their polynomials,
// each coefficient evaluated only when the traversal reads its sign. Deeper
// pieces are derived once each: a split below the precomputed levels halves
// the current piece once (bernstein_halve), the left half becomes current
// and the right half waits on a fixed stack, one slot per level (depth
// first, left first: at most one pending piece per level). The halvings are
// those of deriving each piece from its deepest precomputed ancestor, in the
// same order, so values and bounds are the same bit for bit; only repeated
// work is gone. The stack is per thread and reused: no heap per pixel.
// Shared ends: subdivision keeps a piece's end values, so the left half's
// first coefficient is its parent's first, the right half's last is its
// parent's last, and the right half's first is the left half's last (the
// value at the split point). Their exact values are equal, so are their
// rounded piece polynomials (each rounds the same rational), so are their
// evaluations: down to the precomputed levels each is evaluated once and
// handed on (bit for bit what evaluating it again gives). `root_ends`, if
// given, are the root's first and last coefficients already evaluated with
// the same Monomials (the level-0 test's).
class LazyPieces {
 public:
  LazyPieces(const RegionEntry& e, const Monomials& m, int levels, bool eta, const Bounded* root_ends = nullptr)
      : e_(e), m_(m), levels_(levels), eta_(eta), n1_(eta ? e.n_nu : e.n_xi) {
    static thread_local std::vector<double> scratch;
    const std::size_t need = static_cast<std::size_t>(2 * (kMaxDepth + 3)) * n1_;
    if (scratch.size() < need) scratch.resize(need);
    base_ = scratch.data();
    if (root_ends) {
      first_ = root_ends[0];
      last_ = root_ends[1];
      has_first_ = has_last_ = true;
    }
  }
  int size() const { return n1_; }
  int sign(int k) const { return certain_sign(coeff(k)); }
  void split(int level, int j) {
    if (level > levels_) {
      // Halve the current piece (level - 1) once; from the polynomials at the deepest precomputed level.
      if (level - 1 <= levels_)
        for (int k = 0; k < n1_; ++k) {
          const Bounded b = coeff(k);
          cur()[k] = b.v;
          cur()[n1_ + k] = b.e;
        }
      // bernstein_halve<Bounded>'s values and bounds, bit for bit (halve_bounded.hpp).
      halve_bounded_rows(cur(), cur() + n1_, n1_, slot(level), slot(level) + n1_, work(), work() + n1_);
    } else {
      // The left half keeps the first end; the right half (pending) the last.
      pend_last_[level] = last_;
      has_pend_last_[level] = has_last_;
      has_pend_first_[level] = false;  // set when the left half's last is evaluated
      has_last_ = false;
    }
    select(level, j);
  }
  void next(int level, int j) {
    if (level > levels_) {
      std::copy(slot(level), slot(level) + 2 * n1_, cur());
    } else {
      first_ = pend_first_[level];
      has_first_ = has_pend_first_[level];
      last_ = pend_last_[level];
      has_last_ = has_pend_last_[level];
    }
    select(level, j);
  }

 private:
  void select(int level, int j) {
    level_ = level;
    j_ = j;
    if (level <= levels_) piece_ = (1 << level) - 1 + j;
  }
  // A piece: n1 values, then their n1 bounds.
  double* cur() const { return base_; }
  double* work() const { return base_ + 2 * n1_; }
  double* slot(int level) const { return base_ + static_cast<std::size_t>(2 * (level + 2)) * n1_; }
  Bounded coeff(int k) const {
    if (level_ > levels_) return {cur()[k], cur()[n1_ + k]};
    if (k == 0 && has_first_) return first_;
    if (k == n1_ - 1 && has_last_) return last_;
    const Bounded b = from_poly(k);
    if (k == 0) {
      first_ = b;
      has_first_ = true;
    }
    if (k == n1_ - 1) {
      last_ = b;
      has_last_ = true;
      if (level_ > 0 && (j_ & 1) == 0) {  // a left half: its last is its pending sibling's first
        pend_first_[level_] = b;
        has_pend_first_[level_] = true;
      }
    }
    return b;
  }
  Bounded from_poly(int k) const {
    const std::size_t at = static_cast<std::size_t>(piece_) * n1_ + k;
    return eta_ ? eval_poly(e_.nu[at], m_) : eval_poly(e_.xi[at], m_);
  }
  const RegionEntry& e_;
  const Monomials& m_;
  int levels_;
  bool eta_;
  int n1_;
  int level_ = 0, j_ = 0, piece_ = 0;
  double* base_;  // current piece, work space, then one pending slot per level 1..kMaxDepth
  // The current piece's end values once known (down to the precomputed
  // levels), and per level those of the pending right half.
  mutable Bounded first_{}, last_{};
  mutable bool has_first_ = false, has_last_ = false;
  mutable Bounded pend_first_[kMaxDepth + 1];
  Bounded pend_last_[kMaxDepth + 1];
  mutable bool has_pend_first_[kMaxDepth + 1] = {};
  bool has_pend_last_[kMaxDepth + 1] = {};
};

// The cheapest certified try for one pixel: the root piece's coefficients
// are evaluated once, in plain double, with one error bound E (the largest
// of their bounds); deeper pieces are halved in plain double on a per-thread
// stack, each child's bound E + n1 u max|c| (1 + 2^-20) + tiny (the bound of
// classify.cpp's fast source: halving averages neighbours, and n1 averaging
// steps each round by at most u max|c|). Looser than LazyPieces (whose
// pieces to level kPieceLevels come from exact polynomials), so a pixel
// whose signs are not certain here goes on to LazyPieces, then to the exact
// path: every answer is still Algorithm 1's on the exact coefficients.
class FlatPieces {
 public:
  FlatPieces(const RegionEntry& e, const Monomials& m) : n1_(e.n_xi) {
    static thread_local std::vector<double> scratch;
    const std::size_t need = static_cast<std::size_t>(kMaxDepth + 3) * n1_;
    if (scratch.size() < need) scratch.resize(need);
    base_ = scratch.data();
    for (int k = 0; k < n1_; ++k) {
      const Bounded b = eval_poly(e.xi[k], m);
      base_[k] = b.v;
      e_ = std::max(e_, b.e);
    }
  }
  /// The root piece's coefficients `root` (n1 of them), with one bound `e` on all.
  FlatPieces(const double* root, int n1, double e) : n1_(n1), e_(e) {
    static thread_local std::vector<double> scratch;
    const std::size_t need = static_cast<std::size_t>(kMaxDepth + 3) * n1_;
    if (scratch.size() < need) scratch.resize(need);
    base_ = scratch.data();
    std::copy(root, root + n1, base_);
  }
  int size() const { return n1_; }
  int sign(int k) const {
    const double x = base_[k];
    if (std::fabs(x) > e_) return x > 0 ? 1 : -1;
    return x == 0 && e_ == 0 ? 0 : kSignUnknown;
  }
  void split(int level, int) {
    double mag = 0;
    for (int k = 0; k < n1_; ++k) mag = std::max(mag, std::fabs(base_[k]));
    e_ += n1_ * (0.5 * Bounded::kRound) * mag * (1 + 0x1p-20) + Bounded::kTiny;
    bernstein_halve(base_, n1_, base_, slot(level), base_ + n1_);
    pending_e_[level] = e_;
  }
  void next(int level, int) {
    std::copy(slot(level), slot(level) + n1_, base_);
    e_ = pending_e_[level];
  }

 private:
  double* slot(int level) const { return base_ + static_cast<std::size_t>(level + 2) * n1_; }
  int n1_;
  double e_ = 0;
  double* base_;  // current piece, work space, then one pending slot per level 1..kMaxDepth
  double pending_e_[kMaxDepth + 1];
};

// The first try of the CPU render's pixels (region_cull), prepared once per
// render: each touched entry's root coefficients xi_k(dx, dy) stored
// monomial-major (t[m * n1 + k] = c_km), so that one pixel's n1 values cost
// 10 n1-wide multiply-adds, and per monomial the largest |c_km| over k, so
// that one bound serves every coefficient:
//     E = kPolyErrorUnits u sum_m max_k |c_km| |mu_m| + 16 tiny
// is at least each coefficient's own bound of eval_poly (the same sum with
// |c_km|), of which FlatPieces takes the largest. Level 0 and the traversal
// read the same values, so a pixel evaluates its root coefficients once;
// pixel_root_values (pixel_simd.hpp) evaluates them for 1, 2 or 4 pixels at
// once, bit-identically.
// Looser than classify_fast; a pixel with an uncertain sign here goes on to
// classify_fast, then to the exact path: labels and depths are the exact ones.
struct PixelKernel {
  struct Entry {
    int entry = 0;  ///< index into RegionSetup::entries
    int n1 = 0;
    int offset = 0;  ///< where its values start in a pixel's buffer
    std::vector<double> t;
    std::array<double, kPoly3Terms> mag{};
  };
  std::vector<Entry> entries;
  int values = 0;  ///< sum of n1
  SimdLevel simd = simd_level();  ///< pixels per pixel_root_values call: simd_lanes(simd)
  explicit PixelKernel(const RegionSetup& s) {
    for (std::size_t q = 0; q < s.entries.size(); ++q) {
      const RegionEntry& e = s.entries[q];
      if (!e.classify) continue;
      Entry k;
      k.entry = static_cast<int>(q);
      k.n1 = e.n_xi;
      k.offset = values;
      values += k.n1;
      k.t.assign(static_cast<std::size_t>(kPoly3Terms) * k.n1, 0.0);
      for (int c = 0; c < k.n1; ++c)
        for (int m = 0; m < kPoly3Terms; ++m) {
          const double v = e.xi[c][m];  // the root piece: coefficients 0..n1-1
          k.t[static_cast<std::size_t>(m) * k.n1 + c] = v;
          k.mag[m] = std::max(k.mag[m], std::fabs(v));
        }
      entries.push_back(std::move(k));
    }
  }
};

inline int flat_sign(double x, double e) {
  if (std::fabs(x) > e) return x > 0 ? 1 : -1;  // false for NaN: unknown
  return x == 0 && e == 0 ? 0 : kSignUnknown;
}

// FlatPieces with n1 fixed at compile time (the kernel's common sizes): the
// same halvings (bernstein_halve's order, HalfMean) and the same bound, in
// straight-line code on the stack.
template <int N>
class FlatPiecesN {
 public:
  FlatPiecesN(const double* root, double e) : e_(e) { std::copy(root, root + N, cur_); }
  int size() const { return N; }
  int sign(int k) const { return flat_sign(cur_[k], e_); }
  void split(int level, int) {
    double mag = 0;
    for (int k = 0; k < N; ++k) mag = std::max(mag, std::fabs(cur_[k]));
    e_ += N * (0.5 * Bounded::kRound) * mag * (1 + 0x1p-20) + Bounded::kTiny;
    halve_in_pairs<N>(cur_, pending_[level]);  // bernstein_halve's values, bit for bit
    pending_e_[level] = e_;
  }
  void next(int level, int) {
    std::copy(pending_[level], pending_[level] + N, cur_);
    e_ = pending_e_[level];
  }

 private:
  double e_;
  double cur_[N];
  double pending_[kMaxDepth + 1][N];
  double pending_e_[kMaxDepth + 1];
};

// Algorithm 1 on the kernel's root values of one segment (nullopt: a sign
// not certain with the flat bound). With a record (labels only), the facts
// its block learned replace the nodes' own rules (box_reuse.hpp).
template <class Source>
std::optional<MonotonicityResult> flat_algorithm1(Source& src, int D, const SegmentRecord* record,
                                                  std::uint64_t* reused) {
  MonotonicityFold fold;
  const auto visit = [&](Piece p, int level) { return fold.visit(p, level); };
  if (!(record ? traverse_with_record(src, D, monotonicity_piece, visit, record, *reused)
               : traverse(src, D, monotonicity_piece, visit)))
    return std::nullopt;
  return fold.result(D);
}

std::optional<MonotonicityResult> flat_algorithm1(const double* root, int n1, double e, int D,
                                                  const SegmentRecord* record = nullptr,
                                                  std::uint64_t* reused = nullptr) {
  switch (n1) {
    case 6: {
      FlatPiecesN<6> src(root, e);
      return flat_algorithm1(src, D, record, reused);
    }
    case 10: {
      FlatPiecesN<10> src(root, e);
      return flat_algorithm1(src, D, record, reused);
    }
    case 30: {  // degree 9
      FlatPiecesN<30> src(root, e);
      return flat_algorithm1(src, D, record, reused);
    }
    default: {
      FlatPieces src(root, n1, e);
      return flat_algorithm1(src, D, record, reused);
    }
  }
}

std::optional<MonotonicityResult> lazy_algorithm1(const RegionEntry& e, const Monomials& m, int levels, int D) {
  if (m.point) {
    FlatPieces flat(e, m);
    MonotonicityFold fold;
    if (traverse(flat, D, monotonicity_piece, [&](Piece p, int level) { return fold.visit(p, level); }))
      return fold.result(D);
  }
  LazyPieces src(e, m, levels, false);
  MonotonicityFold fold;
  if (!traverse(src, D, monotonicity_piece, [&](Piece p, int level) { return fold.visit(p, level); }))
    return std::nullopt;
  return fold.result(D);
}

std::optional<InflectionResult> lazy_algorithm2(const RegionEntry& e, const Monomials& m, int levels, int D,
                                                const SegmentRecord* record = nullptr,
                                                std::uint64_t* reused = nullptr) {
  LazyPieces src(e, m, levels, true);
  const int kappa_sign = src.sign(0);
  InflectionFold fold;
  const auto visit = [&](Piece p, int level) { return fold.visit(p, level); };
  if (!(record ? traverse_with_record(src, D, inflection_piece, visit, record, *reused)
               : traverse(src, D, inflection_piece, visit)))
    return std::nullopt;
  return fold.result(D, kappa_sign);
}

// Level 0 of one touched entry: whether its whole-segment end coefficients
// prove non-monotonicity (rule 3 of Algorithm 1) or, in CMR mode, an
// inflection (rule 1 of Algorithm 2), as a three-valued truth.
Truth level0_fails(const RegionEntry& e, const Monomials& mono, bool cmr) {
  const Truth mono_fails = ends_opposite(certain_sign(eval_poly(e.xi[0], mono)),
                                         certain_sign(eval_poly(e.xi[e.n_xi - 1], mono)));
  if (mono_fails == Truth::yes || !cmr) return mono_fails;
  const Truth infl = ends_touch(certain_sign(eval_poly(e.nu[0], mono)), certain_sign(eval_poly(e.nu[e.n_nu - 1], mono)));
  if (infl == Truth::yes) return Truth::yes;
  return mono_fails == Truth::unknown || infl == Truth::unknown ? Truth::unknown : Truth::no;
}

}  // namespace

PixelResult classify_position_exact(const RegionSetup& s, Vec2 p) {
  if (s.fixed_level0_none) return {0, 0, false};
  // In the entries' scale (RegionSetup::scale_exponent): B = B0 + w d, all scaled by 2^-e.
  const Rational dx = scaled(Rational(p.x) - Rational(s.anchor.x), s.scale_exponent),
                 dy = scaled(Rational(p.y) - Rational(s.anchor.y), s.scale_exponent);
  const RegionRequest& o = s.options;
  std::vector<std::vector<Point<Rational>>> B(s.entries.size());
  std::vector<Bernstein<Rational>> xi(s.entries.size()), nu(s.entries.size());
  std::vector<std::vector<HPoint<Rational>>> H(s.entries.size());
  for (std::size_t e = 0; e < s.entries.size(); ++e) {
    const RegionEntry& en = s.entries[e];
    for (std::size_t i = 0; i < en.base_exact.size(); ++i)
      B[e].push_back({en.base_exact[i].x + en.weight_exact[i] * dx, en.base_exact[i].y + en.weight_exact[i] * dy});
    for (std::size_t i = 0; i < en.hw_exact.size(); ++i) H[e].push_back({B[e][i].x, B[e][i].y, en.hw_exact[i]});
    if (!en.classify) continue;
    xi[e] = H[e].empty() ? lambda_bernstein<Rational>(B[e]) : rational_lambda_bernstein<Rational>(H[e]);
    if (ends_opposite(sgn(xi[e].front()), sgn(xi[e].back())) == Truth::yes) return {0, 0, true};
    if (o.mode == Mode::cmr) {
      nu[e] = H[e].empty() ? eta_bernstein<Rational>(B[e]) : rational_d_bernstein<Rational>(H[e]);
      if (ends_touch(sgn(nu[e].front()), sgn(nu[e].back())) == Truth::yes) return {0, 0, true};
    }
  }
  std::vector<SegmentClass> classes = s.verdict.classes;
  for (std::size_t e = 0; e < s.entries.size(); ++e) {
    if (!s.entries[e].classify) continue;
    SegmentClass c;
    c.monotonicity = *algorithm1(xi[e], o.max_depth);
    if (o.mode == Mode::cmr) c.inflection = *algorithm2(nu[e], o.max_depth);
    c.exact_used = true;
    classes[s.verdict.slot[s.entries[e].segment]] = c;
  }
  std::vector<Joint> joints = s.verdict.joints;
  for (const RegionJoint& j : s.varying)
    joints[verdict_joint(s, j)].jump = H[j.left].empty() ? jump_sign<Rational>(B[j.left], B[j.right])
                                                         : jump_sign_homogeneous<Rational>(H[j.left], H[j.right]);
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
  std::vector<std::vector<HPoint<Bounded>>> H(s.entries.size());
  for (std::size_t e = 0; e < s.entries.size(); ++e)
    for (std::size_t i = 0; i < s.entries[e].hw.size(); ++i) H[e].push_back({B[e][i].x, B[e][i].y, s.entries[e].hw[i]});
  for (const RegionJoint& j : s.varying) {
    const int sign = H[j.left].empty() ? jump_sign<Bounded>(B[j.left], B[j.right])
                                       : jump_sign_homogeneous<Bounded>(H[j.left], H[j.right]);
    if (sign == kSignUnknown) return false;
    joints[verdict_joint(s, j)].jump = sign;
  }
  return true;
}

// The certified fast path for a point or a box of displacements: the result
// holds for every displacement in the box, or nullopt when some deciding sign
// is not certain there (then split the box, or for a point go exact).
// bx, by enclose the displacements for the joint computations.
std::optional<PixelResult> classify_fast(const RegionSetup& s, const Monomials& mono, Bounded bx, Bounded by) {
  if (s.fixed_level0_none) return PixelResult{0, 0, false};
  const RegionRequest& o = s.options;
  // Level 0 first: any segment whose end coefficients prove non-monotonicity
  // (or, for CMR, an inflection) decides the pixel.
  bool uncertain = false;
  for (const RegionEntry& e : s.entries) {
    if (!e.classify) continue;
    const Truth fails = level0_fails(e, mono, o.mode == Mode::cmr);
    if (fails == Truth::yes) return PixelResult{0, 0, false};
    uncertain = uncertain || fails == Truth::unknown;
  }
  if (uncertain) return std::nullopt;
  static thread_local std::vector<SegmentClass> classes;  // reused: no heap per pixel
  classes.assign(s.verdict.classes.begin(), s.verdict.classes.end());
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
    classes[s.verdict.slot[e.segment]] = c;
  }
  static thread_local std::vector<Joint> joints;
  joints.assign(s.verdict.joints.begin(), s.verdict.joints.end());
  if (!varying_jumps(s, bx, by, joints)) return std::nullopt;
  return verdict(s, classes, joints, false);
}

// What the failed block around the current pixels learned (cull_block sets
// it around small_block on its thread; null: nothing known), and where the
// pixels count their reuse. Labels only (box_reuse.hpp).
struct PixelReuse {
  const BoxKnowledge* known = nullptr;
  BlockReuseCounts* counts = nullptr;
};
thread_local PixelReuse tl_pixel_reuse;

// classify_fast for one pixel through the render's PixelKernel, on the
// pixel's root values (values[ke.offset + c]) and bounds (bounds[q]) from
// pixel_root_values: nullopt when a sign is not certain with the kernel's one
// bound (then classify_fast).
std::optional<PixelResult> classify_pixel_flat(const RegionSetup& s, const PixelKernel& k, double dx, double dy,
                                               Bounded bx, Bounded by, std::span<const double> values,
                                               std::span<const double> bounds) {
  if (s.fixed_level0_none) return PixelResult{0, 0, false};
  const RegionRequest& o = s.options;
  const bool cmr = o.mode == Mode::cmr;
  // Level 0 first, as classify_fast: any segment failing there decides the pixel.
  bool uncertain = false;
  for (std::size_t q = 0; q < k.entries.size(); ++q) {
    const PixelKernel::Entry& ke = k.entries[q];
    const double* v = values.data() + ke.offset;
    const int n1 = ke.n1;
    const double e = bounds[q];
    Truth fails = ends_opposite(flat_sign(v[0], e), flat_sign(v[n1 - 1], e));
    if (cmr && fails != Truth::yes) {
      const RegionEntry& re = s.entries[ke.entry];
      const Monomials mono(dx, dy);
      const Truth infl = ends_touch(certain_sign(eval_poly(re.nu[0], mono)),
                                    certain_sign(eval_poly(re.nu[re.n_nu - 1], mono)));
      fails = infl == Truth::yes ? Truth::yes
              : (fails == Truth::unknown || infl == Truth::unknown) ? Truth::unknown
                                                                    : Truth::no;
    }
    if (fails == Truth::yes) return PixelResult{0, 0, false};
    uncertain = uncertain || fails == Truth::unknown;
  }
  if (uncertain) return std::nullopt;
  // Without a depth map a segment that fails decides the label (0: its group
  // is "none", and every label kind fails with a failing group), whatever the
  // other segments give; the segment that failed last is tried first, since
  // neighbouring pixels tend to fail on the same one. With a depth map every
  // segment's depth is needed.
  const bool labels_only = !o.depth;
  static thread_local std::size_t first_try = 0;
  const std::size_t n = k.entries.size(), start = labels_only && first_try < n ? first_try : 0;
  // The verdict's template, copied at the first class it receives (a pixel
  // that fails on the first segment tried never needs it).
  static thread_local std::vector<SegmentClass> classes;
  bool classes_copied = false;
  // Labels only: the facts the failed block around this pixel learned.
  const BoxKnowledge* known = labels_only ? tl_pixel_reuse.known : nullptr;
  for (std::size_t step = 0; step < n; ++step) {
    const std::size_t q = (start + step) % n;
    const PixelKernel::Entry& ke = k.entries[q];
    const RegionEntry& e = s.entries[ke.entry];
    const SegmentRecord* rx = known ? &known->xi[ke.entry] : nullptr;
    std::optional<MonotonicityResult> mono;
    if (rx && rx->whole() != NodeFact::none) {  // one direction over the whole block
      ++tl_pixel_reuse.counts->pixel_segments;
      mono = MonotonicityResult{rx->whole() == NodeFact::increasing ? Curvature::increasing : Curvature::decreasing, 0};
    } else {
      mono = flat_algorithm1(values.data() + ke.offset, ke.n1, bounds[q], o.max_depth,
                             rx && !rx->nodes.empty() ? rx : nullptr, known ? &tl_pixel_reuse.counts->pixel_nodes : nullptr);
    }
    if (!mono) {
      uncertain = true;  // another segment may still fail for certain
      continue;
    }
    SegmentClass c;
    c.monotonicity = *mono;
    if (cmr && !(labels_only && c.monotonicity.curvature == Curvature::non_monotone)) {
      const SegmentRecord* rn = known ? &known->nu[ke.entry] : nullptr;
      if (rn && rn->whole() != NodeFact::none) {  // eta of one strict sign over the whole block
        ++tl_pixel_reuse.counts->pixel_segments;
        ++tl_pixel_reuse.counts->eta;
        c.inflection = {Inflection::none, 0, rn->whole() == NodeFact::increasing ? 1 : -1};
      } else {
        const auto i = lazy_algorithm2(e, Monomials(dx, dy), s.piece_levels, o.max_depth,
                                       rn && !rn->nodes.empty() ? rn : nullptr,
                                       known ? &tl_pixel_reuse.counts->eta : nullptr);
        if (!i) {
          uncertain = true;
          continue;
        }
        c.inflection = *i;
      }
    }
    if (labels_only && (c.monotonicity.curvature == Curvature::non_monotone ||
                        (cmr && c.inflection.inflection == Inflection::present))) {
      first_try = q;
      return PixelResult{0, 0, false};
    }
    if (!classes_copied) {
      classes.assign(s.verdict.classes.begin(), s.verdict.classes.end());
      classes_copied = true;
    }
    classes[s.verdict.slot[e.segment]] = c;
  }
  if (uncertain) return std::nullopt;
  if (!classes_copied) classes.assign(s.verdict.classes.begin(), s.verdict.classes.end());
  static thread_local std::vector<Joint> joints;
  joints.assign(s.verdict.joints.begin(), s.verdict.joints.end());
  if (!varying_jumps(s, bx, by, joints)) return std::nullopt;
  return verdict(s, classes, joints, false);
}

// Pixels of the CPU render (count of them, centres p[0..count)) through the
// kernel, in chunks of simd_lanes(k.simd): per touched segment, in the
// kernel's order, the root values and bound of a chunk's pixels at once
// (pixel_root_values: bit-identical at every level), then each pixel's
// level-0 test (ends_opposite of flat_sign of v[0], v[n1 - 1]); a chunk whose
// pixels all failed there skips the later segments. Each pixel not decided
// at level 0 goes on as before, on its computed values: classify_pixel_flat,
// then classify_fast, then the exact path. Writes out[0..count).
void classify_pixels(const RegionSetup& s, const PixelKernel& k, const Vec2* p, int count, PixelResult* out) {
  constexpr int kStrideMax = 64;
  CMR_CHECK(count > 0 && count <= kStrideMax);
  if (s.fixed_level0_none) {
    std::fill(out, out + count, PixelResult{0, 0, false});
    return;
  }
  const int lanes = simd_lanes(k.simd);
  const int stride = (count + lanes - 1) / lanes * lanes;
  double dx[kStrideMax] = {}, dy[kStrideMax] = {};
  bool done[kStrideMax] = {};
  for (int i = 0; i < count; ++i) {
    dx[i] = kernel_displacement(s, p[i].x - s.anchor.x);
    dy[i] = kernel_displacement(s, p[i].y - s.anchor.y);
  }
  static thread_local std::vector<double> batch, bounds, values, pixel_bounds;  // reused: no heap per pixel
  batch.resize(static_cast<std::size_t>(k.values) * stride);
  bounds.resize(k.entries.size() * stride);
  const double units = kPolyErrorUnits * 0.5 * Bounded::kRound, tiny = 16 * Bounded::kTiny;
  for (std::size_t q = 0; q < k.entries.size(); ++q) {
    const PixelKernel::Entry& ke = k.entries[q];
    double* v = batch.data() + static_cast<std::size_t>(ke.offset) * stride;
    double* e = bounds.data() + q * stride;
    for (int first = 0; first < count; first += lanes) {
      const int last = std::min(count, first + lanes);
      if (std::all_of(done + first, done + last, [](bool d) { return d; })) continue;
      pixel_root_values(k.simd, ke.t.data(), ke.mag.data(), ke.n1, dx + first, dy + first, v + first, stride,
                        e + first, units, tiny);
      if (q == 0) count_simd_pixels(k.simd, last - first);
      for (int i = first; i < last; ++i)
        done[i] = done[i] || ends_opposite(flat_sign(v[i], e[i]),
                                           flat_sign(v[static_cast<std::size_t>(ke.n1 - 1) * stride + i], e[i])) ==
                                 Truth::yes;
    }
  }
  values.resize(static_cast<std::size_t>(k.values));
  pixel_bounds.resize(k.entries.size());
  for (int i = 0; i < count; ++i) {
    if (done[i]) {
      out[i] = PixelResult{0, 0, false};
      continue;
    }
    for (int c = 0; c < k.values; ++c) values[c] = batch[static_cast<std::size_t>(c) * stride + i];
    for (std::size_t q = 0; q < k.entries.size(); ++q) pixel_bounds[q] = bounds[q * stride + i];
    const Bounded bx(dx[i], 0.5 * Bounded::kRound * std::fabs(dx[i]));
    const Bounded by(dy[i], 0.5 * Bounded::kRound * std::fabs(dy[i]));
    if (const auto r = classify_pixel_flat(s, k, dx[i], dy[i], bx, by, values, pixel_bounds)) out[i] = *r;
    else if (const auto f = classify_fast(s, Monomials(dx[i], dy[i]), bx, by)) out[i] = *f;
    else out[i] = classify_position_exact(s, p[i]);
  }
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

// How many pieces a block proof may visit per traversal before the block is
// quartered instead. A failed proof is wasted work, so the budget follows
// what the block's pixels would cost: about kBoxPiecesPerPixel pieces per
// pixel, at least kBoxMinPieces (the cheap proofs of large uniform blocks)
// and at most kBoxMaxPieces. Small blocks, which often straddle a region
// boundary and fail, risk little; large blocks, whose pixels would each
// need deep traversals in a zoom onto a boundary, may go as deep as those
// pixels would (a budget of 6 for every block left 99.9% of such a zoom to
// the pixels).
constexpr int kBoxMinPieces = 6, kBoxMaxPieces = 256;
constexpr double kBoxPiecesPerPixel = 0.5;
int box_piece_budget(long pixels) {
  return static_cast<int>(std::clamp<double>(kBoxPiecesPerPixel * static_cast<double>(pixels), kBoxMinPieces,
                                             kBoxMaxPieces));
}

// The block policy of the one traversal: block_piece's rules (decide.hpp),
// folded into one outcome for the whole box.
class BoxFold {
 public:
  bool visit(Piece p) {
    if (p == Piece::non_monotone || p == Piece::inflection) return stop(BoxOutcome::not_monotone);
    if (p == Piece::increasing) inc_ = true;
    else if (p == Piece::decreasing) dec_ = true;
    else return stop(BoxOutcome::unresolved);  // split at level D
    return inc_ && dec_ ? stop(BoxOutcome::not_monotone) : false;
  }
  BoxOutcome result() const { return stop_ ? *stop_ : (inc_ ? BoxOutcome::increasing : BoxOutcome::decreasing); }

 private:
  bool stop(BoxOutcome o) {
    stop_ = o;
    return true;
  }
  bool inc_ = false, dec_ = false;
  std::optional<BoxOutcome> stop_;
};

// With `record` (labels only, box_reuse.hpp): every node's fact is written
// there, and a node whose fact the parent block's record `parent` holds is
// decided by it without evaluating (nor counting against the budget); when
// the traversal stops short, the parent's facts past the last node reached
// are carried over (they hold for this box too).
BoxOutcome box_traversal(const RegionEntry& e, const Monomials& mono, int levels, int D, bool eta, int* kappa,
                         int budget, const SegmentRecord* parent = nullptr, SegmentRecord* record = nullptr,
                         BlockReuseCounts* counts = nullptr, const Bounded* root_ends = nullptr) {
  LazyPieces src(e, mono, levels, eta, root_ends);
  BoxFold fold;
  int visited = 0;
  bool done = false;
  if (!record) {
    // A box that needs many pieces is cheaper to quarter than to resolve.
    const auto rule = [&](const SignSummary& s) {
      return ++visited > budget ? Piece::uncertain : block_piece(s, eta);
    };
    done = traverse(src, D, rule, [&](Piece p, int) { return fold.visit(p); }, true);
  } else {
    RecordReader reader(parent);
    RecordWriter writer(record);
    const auto decide = [&](int level, int j) {
      NodeFact f = reader.at(level, j);
      Piece p;
      if (f != NodeFact::none) {
        ++counts->box_nodes;
        counts->eta += eta;
        p = fact_piece(f);
      } else {
        if (++visited > budget) return Piece::uncertain;
        const SignSummary s = scan_signs(src, true);
        p = block_piece(s, eta);
        if (p == Piece::uncertain) return p;
        f = box_fact(s, p, eta);
      }
      writer.node(level, j, f);
      return p;
    };
    done = traverse_nodes(src, D, decide, [&](Piece p, int) { return fold.visit(p); },
                          [&](int level) { writer.done(level); });
    if ((!done || fold.result() == BoxOutcome::unresolved) && parent) {
      const bool all = record->nodes.empty();
      const std::uint64_t last = all ? 0 : record->nodes.back().key;
      for (const SegmentRecord::Node& n : parent->nodes)
        if (all || n.key > last) record->nodes.push_back(n);
    }
  }
  if (!done) return BoxOutcome::unresolved;
  const BoxOutcome r = fold.result();
  if (kappa) *kappa = r == BoxOutcome::increasing ? 1 : -1;
  return r;
}

// With `out` (labels only, box_reuse.hpp): what the proof learned goes to
// out (for the quarters and pixels when it fails), starting from what the
// parent block learned (`parent`, may be null), whose facts it also uses.
std::optional<PixelResult> classify_box_labels(const RegionSetup& s, const Monomials& mono, Bounded bx, Bounded by,
                                               int budget, const BoxKnowledge* parent = nullptr,
                                               BoxKnowledge* out = nullptr, BlockReuseCounts* counts = nullptr) {
  if (s.fixed_none) return PixelResult{0, 0, false};  // that segment's part is "none" for every position
  const RegionRequest& o = s.options;
  const int D = o.max_depth;
  if (out) {
    // Segments this proof does not reach keep what the parent learned.
    out->reset(s.entries.size());
    if (parent)
      for (std::size_t q = 0; q < s.entries.size(); ++q) {
        out->xi[q].nodes.assign(parent->xi[q].nodes.begin(), parent->xi[q].nodes.end());
        out->nu[q].nodes.assign(parent->nu[q].nodes.begin(), parent->nu[q].nodes.end());
      }
  }
  // The cheapest proof first: a whole segment with opposite end signs. A
  // segment whose xi_0 has no certain sign over the box is not worth a
  // traversal: every piece on the left edge of its subdivision starts with
  // that same coefficient (subdivision keeps it; below the precomputed
  // levels it is copied, above them each piece's polynomial has it), so
  // block_piece splits each of them (no certain leaf, no certain rule 3),
  // and the depth-first traversal goes down that edge first, to level D or
  // to the end of its budget, and fails. It is unresolved at once (always
  // safe: the quarters or the pixels decide; labels cannot change).
  static thread_local std::vector<char> hopeless;
  hopeless.assign(s.entries.size(), 0);
  // xi_0 and xi_last over the box, kept for the traversal's root piece (the same values).
  static thread_local std::vector<std::array<Bounded, 2>> ends;
  static thread_local std::vector<char> have_ends;
  ends.resize(s.entries.size());
  have_ends.assign(s.entries.size(), 0);
  for (std::size_t q = 0; q < s.entries.size(); ++q) {
    const RegionEntry& e = s.entries[q];
    if (!e.classify) continue;
    if (parent && parent->xi[q].level0_no) {  // certain over the parent box, so over this one
      ++counts->box_level0;
      out->xi[q].level0_no = true;
      continue;
    }
    ends[q] = {eval_poly(e.xi[0], mono), eval_poly(e.xi[e.n_xi - 1], mono)};
    have_ends[q] = 1;
    const int first = certain_sign(ends[q][0]), last = certain_sign(ends[q][1]);
    const Truth fails = ends_opposite(first, last);
    if (fails == Truth::yes) return PixelResult{0, 0, false};
    if (out) out->xi[q].level0_no = fails == Truth::no;
    hopeless[q] = first == kSignUnknown;
  }
  static thread_local std::vector<SegmentClass> classes;  // reused: no heap per block
  classes.assign(s.verdict.classes.begin(), s.verdict.classes.end());
  // The segment that failed last (on this thread) is tried first: a failing
  // segment decides the label (0) whatever the others give, and neighbouring
  // blocks tend to fail on the same one.
  const std::size_t n = s.entries.size();
  static thread_local std::size_t first_try = 0;
  const std::size_t start = first_try < n ? first_try : 0;
  for (std::size_t step = 0; step < n; ++step) {
    const std::size_t q = (start + step) % n;
    const RegionEntry& e = s.entries[q];
    if (!e.classify) continue;
    SegmentClass c;
    const SegmentRecord* px = parent ? &parent->xi[q] : nullptr;
    SegmentRecord* ox = out ? &out->xi[q] : nullptr;
    BoxOutcome mono_outcome;
    if (px && px->whole() != NodeFact::none) {  // one direction over the parent: no traversal (out keeps it)
      ++counts->box_segments;
      mono_outcome = px->whole() == NodeFact::increasing ? BoxOutcome::increasing : BoxOutcome::decreasing;
    } else if (hopeless[q]) {
      mono_outcome = BoxOutcome::unresolved;
    } else {
      if (ox) ox->nodes.clear();
      mono_outcome = box_traversal(e, mono, s.piece_levels, D, false, nullptr, budget, px, ox, counts,
                                   have_ends[q] ? ends[q].data() : nullptr);
    }
    switch (mono_outcome) {
      case BoxOutcome::not_monotone: first_try = q; return PixelResult{0, 0, false};
      case BoxOutcome::unresolved: return std::nullopt;  // smaller blocks will do
      case BoxOutcome::increasing: c.monotonicity = {Curvature::increasing, 0}; break;
      case BoxOutcome::decreasing: c.monotonicity = {Curvature::decreasing, 0}; break;
    }
    if (o.mode == Mode::cmr) {
      // For eta, "increasing" means all pieces positive: no inflection, kappa > 0.
      int kappa = 0;
      const SegmentRecord* pn = parent ? &parent->nu[q] : nullptr;
      SegmentRecord* on = out ? &out->nu[q] : nullptr;
      BoxOutcome eta_outcome;
      if (pn && pn->whole() != NodeFact::none) {
        ++counts->box_segments;
        ++counts->eta;
        eta_outcome = pn->whole() == NodeFact::increasing ? BoxOutcome::increasing : BoxOutcome::decreasing;
        kappa = eta_outcome == BoxOutcome::increasing ? 1 : -1;
      } else {
        if (on) on->nodes.clear();
        eta_outcome = box_traversal(e, mono, s.piece_levels, D, true, &kappa, budget, pn, on, counts);
      }
      switch (eta_outcome) {
        case BoxOutcome::not_monotone: first_try = q; return PixelResult{0, 0, false};  // an inflection
        case BoxOutcome::unresolved: return std::nullopt;
        default: c.inflection = {Inflection::none, 0, kappa}; break;
      }
    }
    classes[s.verdict.slot[e.segment]] = c;
  }
  static thread_local std::vector<Joint> joints;
  joints.assign(s.verdict.joints.begin(), s.verdict.joints.end());
  if (!varying_jumps(s, bx, by, joints)) return std::nullopt;
  PixelResult r = verdict(s, classes, joints, false);
  r.depth = 0;
  return r;
}

// The displacements of pixel columns i0..i1 (inclusive), enclosing the exact
// values: the ends are rounded once, so widen them by a relative u; then
// scaled as the kernel takes them (kernel_displacement: NaN where scaling
// would be inexact).
Interval displacement_range(const RegionSetup& s, double first, double last, double anchor) {
  const double lo = first - anchor, hi = last - anchor;
  return {kernel_displacement(s, lo - 0.5 * Bounded::kRound * std::fabs(lo)),
          kernel_displacement(s, hi + 0.5 * Bounded::kRound * std::fabs(hi))};
}

}  // namespace

PixelResult classify_position(const RegionSetup& s, Vec2 p) {
  // dx = fl(p - P_k): one rounding, relative to |dx|, covered by kPolyErrorUnits.
  const double dx = kernel_displacement(s, p.x - s.anchor.x), dy = kernel_displacement(s, p.y - s.anchor.y);
  const Bounded bx(dx, 0.5 * Bounded::kRound * std::fabs(dx)), by(dy, 0.5 * Bounded::kRound * std::fabs(dy));
  if (const auto r = classify_fast(s, Monomials(dx, dy), bx, by)) return *r;
  return classify_position_exact(s, p);
}

namespace {

// classify_block, handing what a failed label proof learned to `out` and
// taking what its parent block learned from `parent` (box_reuse.hpp; both
// null: no reuse).
std::optional<PixelResult> classify_block_with(const RegionSetup& s, int i0, int j0, int i1, int j1,
                                               const BoxKnowledge* parent, BoxKnowledge* out,
                                               BlockReuseCounts* counts) {
  const RegionRequest& o = s.options;
  const View& v = *o.view;
  // Columns run left to right (x grows with i), rows top to bottom (y falls with j).
  const Interval x = displacement_range(s, pixel_center(v, o.width, o.height, i0, 0).x,
                                           pixel_center(v, o.width, o.height, i1, 0).x, s.anchor.x);
  const Interval y = displacement_range(s, pixel_center(v, o.width, o.height, 0, j1).y,
                                           pixel_center(v, o.width, o.height, 0, j0).y, s.anchor.y);
  if (std::isnan(x.lo) || std::isnan(x.hi) || std::isnan(y.lo) || std::isnan(y.hi)) return std::nullopt;
  // Centre and half-width enclosing [lo, hi] despite their rounding.
  const Bounded bx(0.5 * x.lo + 0.5 * x.hi, 0.5 * x.hi - 0.5 * x.lo + Bounded::kRound * x.mag());
  const Bounded by(0.5 * y.lo + 0.5 * y.hi, 0.5 * y.hi - 0.5 * y.lo + Bounded::kRound * y.mag());
  const Monomials mono(bx.v, by.v, bx.e, by.e);
  if (!o.depth)
    return classify_box_labels(s, mono, bx, by, box_piece_budget(static_cast<long>(i1 - i0 + 1) * (j1 - j0 + 1)),
                               parent, out, counts);
  return classify_fast(s, mono, bx, by);
}

}  // namespace

std::optional<PixelResult> classify_block(const RegionSetup& s, int i0, int j0, int i1, int j1) {
  return classify_block_with(s, i0, j0, i1, j1, nullptr, nullptr, nullptr);
}

RegionImage blank_image(const RegionSetup& s) {
  const RegionRequest& o = s.options;
  RegionImage img;
  img.width = o.width;
  img.height = o.height;
  img.view = *o.view;
  img.labels.assign(static_cast<std::size_t>(o.width) * o.height, 0);
  img.depth.assign(img.labels.size(), 0);
  return img;
}

namespace {

constexpr int kPixelsPerSmallBlock = 4;

// Columns i0..i1 and rows j0..j1 of an image, inclusive.
using PixelBlock = std::array<int, 4>;

// Writes a block's label, and its depth when a depth map is wanted (without
// one the depth map stays blank_image's zeros).
void fill(RegionImage& img, const PixelBlock& b, const PixelResult& r, bool depth_map) {
  // A row at a time (byte stores may alias the image's own fields, so a
  // per-pixel loop reloaded its width and data pointers at every pixel).
  const std::size_t width = static_cast<std::size_t>(img.width), n = static_cast<std::size_t>(b[2] - b[0] + 1);
  uint8_t* const labels = img.labels.data();
  uint8_t* const depth = img.depth.data();
  for (int j = b[1]; j <= b[3]; ++j) {
    const std::size_t at = static_cast<std::size_t>(j) * width + static_cast<std::size_t>(b[0]);
    std::memset(labels + at, r.label, n);
    if (depth_map) std::memset(depth + at, r.depth, n);
  }
}

// A block of a few pixels: evaluating the pixels (here, in SIMD chunks
// through classify_pixels, or on the device when min_block > 1) is cheaper
// than a box. Returns the pixels the exact path decided.
std::uint64_t small_block(const RegionSetup& s, const PixelKernel& k, RegionImage& img, const PixelBlock& b,
                          int min_block, std::vector<std::array<int, 2>>& listed) {
  std::uint64_t exact = 0;
  if (min_block > 1) {
    for (int j = b[1]; j <= b[3]; ++j)
      for (int i = b[0]; i <= b[2]; ++i) listed.push_back({i, j});
    return exact;
  }
  CMR_CHECK((b[2] - b[0] + 1) * (b[3] - b[1] + 1) <= kPixelsPerSmallBlock);
  Vec2 p[kPixelsPerSmallBlock];
  PixelResult r[kPixelsPerSmallBlock];
  int n = 0;
  for (int j = b[1]; j <= b[3]; ++j)
    for (int i = b[0]; i <= b[2]; ++i) p[n++] = pixel_center(img.view, img.width, img.height, i, j);
  classify_pixels(s, k, p, n, r);
  n = 0;
  for (int j = b[1]; j <= b[3]; ++j)
    for (int i = b[0]; i <= b[2]; ++i) {
      fill(img, {i, j, i, j}, r[n], s.options.depth);
      exact += r[n++].exact;
    }
  return exact;
}

// Decides one top-level block into img: whole where classify_block holds,
// else quartered; blocks no larger than min_block are listed (single pixels
// with min_block == 1 go through the render's per-pixel path, classify_pixel).
// Returns the pixels the exact path decided.
// Labels only (and unless CMR_BLOCK_REUSE=0), a failed block proof hands
// what it learned to its quarters and, at the end, to its pixels
// (box_reuse.hpp). Blocks are taken depth first, so the knowledge of the
// failed block at quartering depth d (known[d]) stays in place until all of
// its quarters are done.
std::uint64_t cull_block(const RegionSetup& s, const PixelKernel& k, RegionImage& img, const PixelBlock& top,
                         int min_block, std::vector<std::array<int, 2>>& listed) {
  std::uint64_t exact = 0;
  const bool reuse = !s.options.depth && block_reuse();
  static thread_local std::vector<BoxKnowledge> known;  // reused: no heap per block
  BlockReuseCounts counts;
  std::vector<std::pair<PixelBlock, int>> todo{{top, 0}};  // with its quartering depth
  while (!todo.empty()) {
    const auto [b, d] = todo.back();
    const auto [i0, j0, i1, j1] = b;
    todo.pop_back();
    if (reuse && known.size() <= static_cast<std::size_t>(d)) known.resize(static_cast<std::size_t>(d) + 1);
    const BoxKnowledge* parent = reuse && d > 0 ? &known[static_cast<std::size_t>(d) - 1] : nullptr;
    if ((i1 - i0 + 1) * (j1 - j0 + 1) <= kPixelsPerSmallBlock) {
      tl_pixel_reuse = {parent, &counts};
      exact += small_block(s, k, img, b, min_block, listed);
      tl_pixel_reuse = {};
    } else if (const auto r = classify_block_with(s, i0, j0, i1, j1, parent,
                                                  reuse ? &known[static_cast<std::size_t>(d)] : nullptr, &counts)) {
      fill(img, b, *r, s.options.depth);
    } else if (i1 - i0 < min_block && j1 - j0 < min_block) {
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) listed.push_back({i, j});
    } else {
      const int im = (i0 + i1) / 2, jm = (j0 + j1) / 2;
      todo.push_back({{i0, j0, im, jm}, d + 1});
      if (im < i1) todo.push_back({{im + 1, j0, i1, jm}, d + 1});
      if (jm < j1) todo.push_back({{i0, jm + 1, im, j1}, d + 1});
      if (im < i1 && jm < j1) todo.push_back({{im + 1, jm + 1, i1, j1}, d + 1});
    }
  }
  add_block_reuse_counts(counts);
  publish_simd_pixel_counts();
  return exact;
}

}  // namespace

std::vector<std::array<int, 2>> region_cull(const RegionSetup& s, RegionImage& img, int min_block, int threads) {
  const RegionRequest& o = s.options;
  if (!o.depth && s.fixed_none) return {};  // every label is 0 (img is all zero)
  // Blocks of kRegionBlock pixels, one job each; blocks write disjoint pixels.
  const int bw = (o.width + kRegionBlock - 1) / kRegionBlock, bh = (o.height + kRegionBlock - 1) / kRegionBlock;
  std::vector<std::vector<std::array<int, 2>>> listed(static_cast<std::size_t>(bw) * bh);
  std::vector<std::uint64_t> exact(listed.size(), 0);
  const PixelKernel kernel(s);
  WorkerPool::shared().run(listed.size(), threads, [&](std::size_t b) {
    if (o.cancel != nullptr && o.cancel->load(std::memory_order_relaxed)) return;  // the result is dropped
    const int bi = static_cast<int>(b) % bw, bj = static_cast<int>(b) / bw;
    const PixelBlock top{bi * kRegionBlock, bj * kRegionBlock, std::min(o.width, (bi + 1) * kRegionBlock) - 1,
                         std::min(o.height, (bj + 1) * kRegionBlock) - 1};
    exact[b] = cull_block(s, kernel, img, top, min_block, listed[b]);
  });
  for (const std::uint64_t e : exact) img.exact_pixels += e;
  std::vector<std::array<int, 2>> out;
  for (const auto& l : listed) out.insert(out.end(), l.begin(), l.end());
  return out;
}

RegionImage region_cpu(const RegionSetup& s, int threads) {
  RegionImage img = blank_image(s);
  region_cull(s, img, 1, threads);
  return img;
}

}  // namespace cmr::backend
