#include "region/kernel.hpp"
#include "region/region_setup.hpp"

#include "bezierize/algorithms.hpp"

#include <algorithm>
#include <cmath>

#include "bezierize/lambda.hpp"
#include "numeric/poly3.hpp"
#include "bezierize/rational_lambda.hpp"
#include "region/region_pieces.hpp"
#include "spline/errors.hpp"

// The host setup of a region problem (region_setup.hpp): the point group,
// the segments the move touches, the verdict template that folds the fixed
// runs, and the entries' exact and rounded points and piece polynomials.
// The pixel kernel that reads it is in region.cpp, the block proofs in block.cpp.

namespace cmr::backend {

using namespace detail;  // the kernel's shared parts (kernel.hpp)

namespace {

double rounded(const Rational& q) { return q.get_d(); }

}  // namespace

namespace detail {

// q 2^-e, exactly.
Rational scaled(Rational q, int e) {
  if (e > 0) mpq_div_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(e));
  if (e < 0) mpq_mul_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(-e));
  return q;
}

}  // namespace detail

namespace {


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

}  // namespace cmr::backend
