#include "region/kernel.hpp"
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
#include "region/pixel_lanes.hpp"
#include "region/pixel_simd.hpp"
#include "numeric/poly3.hpp"
#include "bezierize/rational_lambda.hpp"
#include "region/region_pieces.hpp"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"

// The CPU backend's pixel kernel (region_setup.hpp): the pieces of a pixel's
// polynomials, Algorithms 1 and 2 on them with certified bounds, the verdict,
// the exact fallback and the SIMD chunks of the render's pixels. The setup is
// in setup.cpp, the block proofs and the cull in block.cpp.

namespace cmr::backend {

using namespace detail;  // the kernel's shared parts (kernel.hpp)

namespace {

// A varying joint's index in the verdict template: it sits before its right
// segment, which is an entry and so has a slot of its own.
int verdict_joint(const RegionSetup& s, const RegionJoint& j) {
  // The seam follows segment N-1 (the template's neutral class comes after it).
  if (j.seam) return s.verdict.slot[s.entries[j.left].segment];
  return s.verdict.slot[s.entries[j.right].segment] - 1;
}

}  // namespace

namespace detail {

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

}  // namespace detail

namespace {

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
  int sign(int k) const { return flat_sign(base_[k], e_); }
  void split(int level, int) {
    double mag = 0;
    for (int k = 0; k < n1_; ++k) mag = std::max(mag, std::fabs(base_[k]));
    grow_halving_bound(e_, n1_, mag);
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
    grow_halving_bound(e_, N, mag);
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
  // GMP raises SIGFPE on converting NaN or an infinity. A pixel centre is
  // finite (the view is checked) and RegionProblem::classify refuses such a
  // position; only a search's overflowed arithmetic (design/fix.cpp, a
  // curve near the top of the double range) asks here: no region has it.
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) return {0, 0, true};
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

namespace detail {

// part_verdict's "none" only grows as classes and jumps are filled in: its
// flags (increasing, decreasing, not monotone, an inflection) are only ever
// set, "none" is one of them or both directions together, a joint's
// conflict needs a direction and a non-zero jump, and two certain curvature
// signs that differ leave a change of sign between neighbours in any
// sequence that holds them. So a group that is "none" with the unknown
// classes neutral (neutral_class: read as nothing) and the varying jumps 0
// is "none" for every position, and with it the label (a failing group
// fails every label kind, as the block proof's shortcut already takes it).
bool fails_whatever_unknown(const RegionSetup& s, std::vector<SegmentClass>& classes,
                            const std::vector<char>& unknown) {
  const SegmentClass neutral = neutral_class();
  for (std::size_t q = 0; q < s.entries.size(); ++q) {
    if (!unknown[q]) continue;
    SegmentClass& c = classes[s.verdict.slot[s.entries[q].segment]];
    if (unknown[q] & 1) c.monotonicity = neutral.monotonicity;
    if (unknown[q] & 2) c.inflection = neutral.inflection;
  }
  static thread_local std::vector<Joint> joints;
  joints.assign(s.verdict.joints.begin(), s.verdict.joints.end());
  for (const RegionJoint& j : s.varying) joints[verdict_joint(s, j)].jump = 0;
  const std::vector<int>& starts = s.verdict.starts;
  for (std::size_t g = 0; g < starts.size(); ++g) {
    const int end = g + 1 < starts.size() ? starts[g + 1] : static_cast<int>(classes.size());
    if (part_verdict(classes, joints, starts[g], end, s.options.mode) == Direction::none) return true;
  }
  return false;
}

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

thread_local PixelReuse tl_pixel_reuse;

}  // namespace detail

namespace {

// Algorithm 1 of the pixels of one classify_pixels call, in lock step
// (pixel_lanes.hpp): the first time a pixel asks for entry q, q is traversed
// for it and for up to kPixelLanes - 1 more of the call's pixels after it
// that are still undecided, and each keeps its own answer for when it asks
// (a pixel that stops before asking wasted a lane). The pixels of a call
// are one small block's, so they share its block record (tl_pixel_reuse).
class LaneResults {
 public:
  LaneResults(const PixelKernel& k, const double* batch, const double* bounds, std::size_t stride, const bool* done,
              int count, int D)
      : k_(k), batch_(batch), bounds_(bounds), stride_(stride), done_(done), count_(count), D_(D) {
    static thread_local std::vector<std::optional<MonotonicityResult>> results;
    static thread_local std::vector<char> have;
    results.resize(k.entries.size() * static_cast<std::size_t>(count));
    have.assign(results.size(), 0);
    results_ = results.data();
    have_ = have.data();
  }
  /// Entry q's answer at pixel i; `record` (may be null) is the block's,
  /// the same for every pixel of the call, and `reused` its count.
  const std::optional<MonotonicityResult>& at(std::size_t q, int i, const SegmentRecord* record,
                                              std::uint64_t* reused) {
    const std::size_t slot = q * static_cast<std::size_t>(count_);
    if (!have_[slot + static_cast<std::size_t>(i)]) {
      int pixel[kPixelLanes], lanes = 0;
      for (int p = i; p < count_ && lanes < kPixelLanes; ++p)
        if (!done_[p] && !have_[slot + static_cast<std::size_t>(p)]) pixel[lanes++] = p;
      const PixelKernel::Entry& ke = k_.entries[q];
      const double* v = batch_ + static_cast<std::size_t>(ke.offset) * stride_;
      double e[kPixelLanes];
      for (int l = 0; l < lanes; ++l) e[l] = bounds_[q * stride_ + static_cast<std::size_t>(pixel[l])];
      std::optional<MonotonicityResult> out[kPixelLanes];
      switch (ke.n1) {
        case 6: flat_algorithm1_lanes<6>(v, stride_, pixel, e, lanes, D_, record, reused, out); break;
        case 10: flat_algorithm1_lanes<10>(v, stride_, pixel, e, lanes, D_, record, reused, out); break;
        default: flat_algorithm1_lanes<30>(v, stride_, pixel, e, lanes, D_, record, reused, out); break;
      }
      count_pixel_lane_traversals(lanes);
      for (int l = 0; l < lanes; ++l) {
        results_[slot + static_cast<std::size_t>(pixel[l])] = out[l];
        have_[slot + static_cast<std::size_t>(pixel[l])] = 1;
      }
    }
    return results_[slot + static_cast<std::size_t>(i)];
  }
  /// Whether entry q's traversal runs in lock step: the sizes compiled
  /// (cubic, quartic, degree 9). (The lock step runs at the AVX2 level only:
  /// classify_pixels makes no LaneResults at another.)
  bool takes(std::size_t q) const {
    const int n1 = k_.entries[q].n1;
    return n1 == 6 || n1 == 10 || n1 == 30;
  }

 private:
  const PixelKernel& k_;
  const double* batch_;
  const double* bounds_;
  std::size_t stride_;
  const bool* done_;
  int count_, D_;
  std::optional<MonotonicityResult>* results_;
  char* have_;
};

// classify_fast for one pixel through the render's PixelKernel, on the
// pixel's root values (values[ke.offset + c]) and bounds (bounds[q]) from
// pixel_root_values: nullopt when a sign is not certain with the kernel's one
// bound (then classify_fast). With `lanes`, this is pixel `pixel` of its
// classify_pixels call, and Algorithm 1 (with its block's record, where it
// has one) comes from the lock-step traversal: the same answer. `uniform`
// (may be null): per kernel entry, whether the failed block around the pixel
// found it of one direction over the whole block (classify_pixels: its
// values were not computed).
std::optional<PixelResult> classify_pixel_flat(const RegionSetup& s, const PixelKernel& k, double dx, double dy,
                                               Bounded bx, Bounded by, std::span<const double> values,
                                               std::span<const double> bounds, LaneResults* lanes = nullptr,
                                               int pixel = 0, const char* uniform = nullptr) {
  if (s.fixed_level0_none) return PixelResult{0, 0, false};
  const RegionRequest& o = s.options;
  const bool cmr = o.mode == Mode::cmr;
  // Level 0 first, as classify_fast: any segment failing there decides the
  // pixel. An entry of one direction over the block cannot fail there (its
  // ends are certainly not opposite at every pixel of it).
  bool uncertain = false;
  for (std::size_t q = 0; q < k.entries.size(); ++q) {
    const PixelKernel::Entry& ke = k.entries[q];
    const double* v = values.data() + ke.offset;
    const int n1 = ke.n1;
    const double e = bounds[q];
    Truth fails = uniform && uniform[q] ? Truth::no : ends_opposite(flat_sign(v[0], e), flat_sign(v[n1 - 1], e));
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
    // Plain locals, and the class written field by field into its slot at
    // the end: building a SegmentClass (and an optional) on the stack and
    // copying it whole reloaded bytes just stored as narrower fields, two
    // store-forwarding stalls per segment (a fifth of this function's time).
    MonotonicityResult mono;
    if (rx && rx->whole() != NodeFact::none) {  // one direction over the whole block
      ++tl_pixel_reuse.counts->pixel_segments;
      mono = {rx->whole() == NodeFact::increasing ? Curvature::increasing : Curvature::decreasing, 0};
    } else {
      const SegmentRecord* record = rx && !rx->nodes.empty() ? rx : nullptr;
      std::uint64_t* nodes = known ? &tl_pixel_reuse.counts->pixel_nodes : nullptr;
      const std::optional<MonotonicityResult> m =
          lanes && lanes->takes(q) ? lanes->at(q, pixel, record, nodes)
                                   : flat_algorithm1(values.data() + ke.offset, ke.n1, bounds[q], o.max_depth, record,
                                                     nodes);
      if (!m) {
        uncertain = true;  // another segment may still fail for certain
        continue;
      }
      mono = *m;
    }
    InflectionResult inflection;
    if (cmr && !(labels_only && mono.curvature == Curvature::non_monotone)) {
      const SegmentRecord* rn = known ? &known->nu[ke.entry] : nullptr;
      if (rn && rn->whole() != NodeFact::none) {  // eta of one strict sign over the whole block
        ++tl_pixel_reuse.counts->pixel_segments;
        ++tl_pixel_reuse.counts->eta;
        inflection = {Inflection::none, 0, rn->whole() == NodeFact::increasing ? 1 : -1};
      } else {
        const auto i = lazy_algorithm2(e, Monomials(dx, dy), s.piece_levels, o.max_depth,
                                       rn && !rn->nodes.empty() ? rn : nullptr,
                                       known ? &tl_pixel_reuse.counts->eta : nullptr);
        if (!i) {
          uncertain = true;
          continue;
        }
        inflection = *i;
      }
    }
    if (labels_only && (mono.curvature == Curvature::non_monotone ||
                        (cmr && inflection.inflection == Inflection::present))) {
      first_try = q;
      return PixelResult{0, 0, false};
    }
    if (!classes_copied) {
      classes.assign(s.verdict.classes.begin(), s.verdict.classes.end());
      classes_copied = true;
    }
    SegmentClass& c = classes[s.verdict.slot[e.segment]];
    c.monotonicity.curvature = mono.curvature;
    c.monotonicity.depth = mono.depth;
    c.inflection.inflection = inflection.inflection;
    c.inflection.depth = inflection.depth;
    c.inflection.kappa_sign = inflection.kappa_sign;
    c.exact_used = false;
  }
  if (uncertain) return std::nullopt;
  if (!classes_copied) classes.assign(s.verdict.classes.begin(), s.verdict.classes.end());
  static thread_local std::vector<Joint> joints;
  joints.assign(s.verdict.joints.begin(), s.verdict.joints.end());
  if (!varying_jumps(s, bx, by, joints)) return std::nullopt;
  return verdict(s, classes, joints, false);
}

}  // namespace

namespace detail {

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
  // Only the pixels and a chunk's padding lanes up to stride are read (the
  // padding as zeros): no 1 KiB of zeros a call.
  double dx[kStrideMax], dy[kStrideMax];
  bool done[kStrideMax];
  std::fill(dx + count, dx + stride, 0.0);
  std::fill(dy + count, dy + stride, 0.0);
  std::fill(done, done + stride, false);
  for (int i = 0; i < count; ++i) {
    dx[i] = kernel_displacement(s, p[i].x - s.anchor.x);
    dy[i] = kernel_displacement(s, p[i].y - s.anchor.y);
  }
  static thread_local std::vector<double> batch, bounds, values, pixel_bounds;  // reused: no heap per pixel
  batch.resize(static_cast<std::size_t>(k.values) * stride);
  bounds.resize(k.entries.size() * stride);
  const double units = kPolyErrorUnits * 0.5 * Bounded::kRound, tiny = 16 * Bounded::kTiny;
  // Labels only, in a small block whose failed proof found an entry of one
  // direction over the whole block (its record's root is increasing or
  // decreasing: box_reuse.hpp): at every pixel Algorithm 1 gives that
  // direction and its level 0 cannot fail, and no traversal reads its
  // values, so they are not computed (uniform[q]).
  static thread_local std::vector<char> uniform_flags;
  const char* uniform = nullptr;
  if (const BoxKnowledge* known = !s.options.depth ? tl_pixel_reuse.known : nullptr) {
    uniform_flags.resize(k.entries.size());
    for (std::size_t q = 0; q < k.entries.size(); ++q)
      uniform_flags[q] = known->xi[k.entries[q].entry].whole() != NodeFact::none;
    uniform = uniform_flags.data();
  }
  for (std::size_t q = 0; q < k.entries.size(); ++q) {
    const PixelKernel::Entry& ke = k.entries[q];
    if (uniform && uniform[q]) continue;
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
  // Several undecided pixels: their traversals in lock step (pixel_lanes.hpp).
  const bool lock_step = pixel_lanes() && k.simd == SimdLevel::avx2 && std::count(done, done + count, false) > 1;
  std::optional<LaneResults> lane_results;
  if (lock_step)
    lane_results.emplace(k, batch.data(), bounds.data(), static_cast<std::size_t>(stride), done, count,
                         s.options.max_depth);
  for (int i = 0; i < count; ++i) {
    if (done[i]) {
      out[i] = PixelResult{0, 0, false};
      continue;
    }
    for (int c = 0; c < k.values; ++c) values[c] = batch[static_cast<std::size_t>(c) * stride + i];
    for (std::size_t q = 0; q < k.entries.size(); ++q) pixel_bounds[q] = bounds[q * stride + i];
    const Bounded bx(dx[i], 0.5 * Bounded::kRound * std::fabs(dx[i]));
    const Bounded by(dy[i], 0.5 * Bounded::kRound * std::fabs(dy[i]));
    if (const auto r = classify_pixel_flat(s, k, dx[i], dy[i], bx, by, values, pixel_bounds,
                                           lane_results ? &*lane_results : nullptr, i, uniform))
      out[i] = *r;
    else if (const auto f = classify_fast(s, Monomials(dx[i], dy[i]), bx, by)) out[i] = *f;
    else out[i] = classify_position_exact(s, p[i]);
  }
}

}  // namespace detail

PixelResult classify_position(const RegionSetup& s, Vec2 p) {
  // dx = fl(p - P_k): one rounding, relative to |dx|, covered by kPolyErrorUnits.
  const double dx = kernel_displacement(s, p.x - s.anchor.x), dy = kernel_displacement(s, p.y - s.anchor.y);
  const Bounded bx(dx, 0.5 * Bounded::kRound * std::fabs(dx)), by(dy, 0.5 * Bounded::kRound * std::fabs(dy));
  if (const auto r = classify_fast(s, Monomials(dx, dy), bx, by)) return *r;
  return classify_position_exact(s, p);
}

}  // namespace cmr::backend
