#include "region/kernel.hpp"
#include "region/pixel_lanes.hpp"
#include "region/region_setup.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "spline/errors.hpp"
#include "spline/parallel.hpp"

// The CPU backend's block proofs (region_setup.hpp): whole boxes of pixels
// decided at once, the quartering cull of a render down to small blocks and
// pixels, and region_cpu. The pixel kernel they fall back on is in region.cpp.

namespace cmr::backend {

using namespace detail;  // the kernel's shared parts (kernel.hpp)

namespace {


// Polynomial in (dx, dy) with its certified error bound.
// A closed interval of reals.
struct Interval {
  double lo, hi;
  double mag() const { return std::max(std::fabs(lo), std::fabs(hi)); }
};

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

// This thread's blocks decided by a witness, and with a segment left
// unresolved (fails_whatever_unknown), published once per block job.
thread_local std::uint64_t tl_witness_blocks = 0;
thread_local std::uint64_t tl_unknown_blocks = 0;
// Whether this thread's last block proof was decided by a witness.
thread_local bool tl_witness_decided = false;

// A witness that the segment of `e` is not monotone at every position of
// the box: a dyadic piece of level <= levels (the precomputed ones) whose
// end values certainly have opposite signs. Every position's Algorithm 1
// then answers "not monotone": no ancestor of that piece can be decided
// increasing or decreasing there (all its coefficients would have one sign,
// and so would the piece's), an ancestor is never left undecided (levels <=
// D), and no other outcome stops a traversal before it reaches the piece.
// The box traversal cannot find such a piece past one it leaves unresolved
// (it stops there): along a curve where a root of lambda crosses a dyadic
// point (one piece's end on one side of the curve, the next piece's on the
// other), every block went down to the pixels although every pixel fails.
// A piece's end values are lambda's values at dyadic points: the first
// coefficients of the pieces at level `levels`, and the last piece's last
// (equal rounded polynomials for equal exact values: LazyPieces).
enum class Witness { found, none, none_for_quarters };
Witness not_monotone_witness(const RegionEntry& e, const Monomials& mono, int levels) {
  const int n1 = e.n_xi, pieces = 1 << levels;
  const std::array<double, kPoly3Terms>* rows[(1 << kPieceLevels) + 1];
  for (int j = 0; j < pieces; ++j) rows[j] = &e.xi[static_cast<std::size_t>(pieces - 1 + j) * n1];
  rows[pieces] = &e.xi[static_cast<std::size_t>(2 * pieces - 2) * n1 + n1 - 1];
  Bounded at[(1 << kPieceLevels) + 1];
  box_eval::eval_polys(simd_level(), rows, pieces + 1, mono, at);
  int sign[(1 << kPieceLevels) + 1] = {};  // 0..pieces are set below; zeroed so that GCC sees it
  bool pos = false, neg = false, inner_unknown = false;
  for (int j = 0; j <= pieces; ++j) {
    sign[j] = certain_sign(at[j]);
    pos = pos || sign[j] == 1;
    neg = neg || sign[j] == -1;
    inner_unknown = inner_unknown || (j > 0 && j < pieces && sign[j] == kSignUnknown);
  }
  // One certain sign s and no unknown inner value: in a sub-box the certain
  // values keep s (the exact values do), so a witness there needs an end at
  // -s against a value at s; with the other end certain at s, that is the
  // whole segment's ends, which the sub-box's level-0 test catches first.
  if (!(pos && neg) && !inner_unknown && !(sign[0] == kSignUnknown && sign[pieces] == kSignUnknown))
    return Witness::none_for_quarters;
  for (int step = pieces; step >= 1; step /= 2)
    for (int a = 0; a + step <= pieces; a += step)
      if (ends_opposite(sign[a], sign[a + step]) == Truth::yes) return Witness::found;
  return Witness::none;
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
        out->xi[q].no_witness = parent->xi[q].no_witness;
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
  // Likewise when xi_last has no certain sign: every piece on the right edge
  // ends with it, so no traversal can prove a direction, only "not
  // monotone" from a piece left of that edge, after its descent of the left
  // pieces and of the right edge to level D. The witness search (on the
  // unresolved segment) still looks for a piece with opposite end signs;
  // what is lost is only such a piece below level 3 or a mix of directions
  // left of the edge. In a boundary zoom where a root leaves the span
  // through t = 1 this halved the cubic Bezier's frame (docs/performance.md).
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
    hopeless[q] = first == kSignUnknown || last == kSignUnknown;
  }
  static thread_local std::vector<SegmentClass> classes;  // reused: no heap per block
  classes.assign(s.verdict.classes.begin(), s.verdict.classes.end());
  // The segment that failed last (on this thread) is tried first: a failing
  // segment decides the label (0) whatever the others give, and neighbouring
  // blocks tend to fail on the same one.
  const std::size_t n = s.entries.size();
  static thread_local std::size_t first_try = 0;
  const std::size_t start = first_try < n ? first_try : 0;
  // With several segments, one left unresolved over the box does not end the
  // proof: the others may still make the label 0 for every position
  // (fails_whatever_unknown: e.g. one certainly increasing and another
  // certainly decreasing), as along the curves inside the failing area where
  // one segment changes from failing to monotone while two others disagree.
  static thread_local std::vector<char> unknown;
  unknown.assign(n, 0);
  bool unresolved = false;
  const bool several =
      !(parent && parent->others_decide_nothing) &&
      std::count_if(s.entries.begin(), s.entries.end(), [](const RegionEntry& e) { return e.classify; }) > 1;
  if (out && parent) out->others_decide_nothing = parent->others_decide_nothing;
  // Past an unresolved entry the others get the smallest budget: they only
  // matter when they are decided simply, and a traversal that fails costs
  // its whole budget.
  const int rest_budget = std::min(budget, kBoxMinPieces);
  // After a block that a witness decided, the thread's next one (mostly its
  // neighbour, in the same failing area) looks for a witness before each
  // traversal instead of after it: the order changes no label (each proves
  // its own outcome), only which one is paid for first.
  const bool witness_first = tl_witness_decided && witness_search();
  tl_witness_decided = false;
  const auto decided_by_witness = [&](std::size_t q) {
    first_try = q;
    ++tl_witness_blocks;
    tl_witness_decided = true;
    return PixelResult{0, 0, false};
  };
  for (std::size_t step = 0; step < n; ++step) {
    const std::size_t q = (start + step) % n;
    const RegionEntry& e = s.entries[q];
    if (!e.classify) continue;
    SegmentClass c;
    const SegmentRecord* px = parent ? &parent->xi[q] : nullptr;
    SegmentRecord* ox = out ? &out->xi[q] : nullptr;
    BoxOutcome mono_outcome;
    std::optional<Witness> early;  // the witness search made before the traversal
    if (px && px->whole() != NodeFact::none) {  // one direction over the parent: no traversal (out keeps it)
      ++counts->box_segments;
      mono_outcome = px->whole() == NodeFact::increasing ? BoxOutcome::increasing : BoxOutcome::decreasing;
    } else if (hopeless[q]) {
      mono_outcome = BoxOutcome::unresolved;
    } else {
      if (witness_first && !(px && px->no_witness)) {
        early = not_monotone_witness(e, mono, s.piece_levels);
        if (*early == Witness::found) return decided_by_witness(q);
      }
      if (ox) ox->nodes.clear();
      mono_outcome = box_traversal(e, mono, s.piece_levels, D, false, nullptr, unresolved ? rest_budget : budget, px,
                                   ox, counts, have_ends[q] ? ends[q].data() : nullptr);
    }
    switch (mono_outcome) {
      case BoxOutcome::not_monotone: first_try = q; return PixelResult{0, 0, false};
      case BoxOutcome::unresolved:
        if (!(px && px->no_witness) && witness_search()) {
          const Witness w = early ? *early : not_monotone_witness(e, mono, s.piece_levels);
          if (w == Witness::found) return decided_by_witness(q);
          if (ox) ox->no_witness = w == Witness::none_for_quarters;
        }
        if (!several) return std::nullopt;  // smaller blocks will do
        unknown[q] = 1 | 2;
        unresolved = true;
        continue;
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
        eta_outcome =
            box_traversal(e, mono, s.piece_levels, D, true, &kappa, unresolved ? rest_budget : budget, pn, on, counts);
      }
      switch (eta_outcome) {
        case BoxOutcome::not_monotone: first_try = q; return PixelResult{0, 0, false};  // an inflection
        case BoxOutcome::unresolved:
          if (!several) return std::nullopt;
          classes[s.verdict.slot[e.segment]] = c;
          unknown[q] = 2;
          unresolved = true;
          continue;
        default: c.inflection = {Inflection::none, 0, kappa}; break;
      }
    }
    classes[s.verdict.slot[e.segment]] = c;
  }
  if (unresolved) {
    if (!fails_whatever_unknown(s, classes, unknown)) {
      const auto zeros = std::count(unknown.begin(), unknown.end(), 0);
      if (out) out->others_decide_nothing = n - static_cast<std::size_t>(zeros) == 1;  // one entry unknown
      return std::nullopt;  // smaller blocks will do
    }
    ++tl_unknown_blocks;
    return PixelResult{0, 0, false};
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

// Centre and half-width enclosing [lo, hi] despite their rounding.
Bounded enclosing(Interval r) {
  return {0.5 * r.lo + 0.5 * r.hi, 0.5 * r.hi - 0.5 * r.lo + Bounded::kRound * r.mag()};
}

}  // namespace

namespace {

// classify_block, handing what a failed label proof learned to `out` and
// taking what its parent block learned from `parent` (box_reuse.hpp; both
// null: no reuse).
std::optional<PixelResult> classify_block_with(const RegionSetup& s, int i0, int j0, int i1, int j1,
                                               const BoxKnowledge* parent, BoxKnowledge* out,
                                               BlockReuseCounts* counts) {
  const RegionRequest& o = s.options;
  const Bounded bx = block_columns(s, i0, i1), by = block_rows(s, j0, j1);
  if (std::isnan(bx.v) || std::isnan(bx.e) || std::isnan(by.v) || std::isnan(by.e)) {
    if (out) out->reset(s.entries.size());  // learned nothing: the quarters must not read an earlier block's facts
    return std::nullopt;
  }
  const Monomials mono(bx.v, by.v, bx.e, by.e);
  if (!o.depth)
    return classify_box_labels(s, mono, bx, by, box_piece_budget(static_cast<long>(i1 - i0 + 1) * (j1 - j0 + 1)),
                               parent, out, counts);
  return classify_fast(s, mono, bx, by);
}

}  // namespace

Bounded block_columns(const RegionSetup& s, int i0, int i1) {
  // Columns run left to right (x grows with i).
  const RegionRequest& o = s.options;
  return enclosing(displacement_range(s, pixel_center(*o.view, o.width, o.height, i0, 0).x,
                                      pixel_center(*o.view, o.width, o.height, i1, 0).x, s.anchor.x));
}

Bounded block_rows(const RegionSetup& s, int j0, int j1) {
  // Rows run top to bottom (y falls with j).
  const RegionRequest& o = s.options;
  return enclosing(displacement_range(s, pixel_center(*o.view, o.width, o.height, 0, j1).y,
                                      pixel_center(*o.view, o.width, o.height, 0, j0).y, s.anchor.y));
}

std::optional<PixelResult> classify_block(const RegionSetup& s, int i0, int j0, int i1, int j1) {
  return classify_block_with(s, i0, j0, i1, j1, nullptr, nullptr, nullptr);
}

RegionImage blank_image(const RegionSetup& s) {
  const RegionRequest& o = s.options;
  RegionImage img;
  img.width = o.width;
  img.height = o.height;
  img.view = *o.view;
  img.labels = LabelCodes(labels_of(o), static_cast<std::size_t>(o.width) * o.height);
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

// A block of a few pixels, which the CPU's kernel decides (in SIMD chunks
// through classify_pixels) for less than a box proof costs. Returns the
// pixels the exact path decided.
std::uint64_t small_block(const RegionSetup& s, const PixelKernel& k, RegionImage& img, const PixelBlock& b) {
  std::uint64_t exact = 0;
  CMR_CHECK((b[2] - b[0] + 1) * (b[3] - b[1] + 1) <= kPixelsPerSmallBlock);
  Vec2 p[kPixelsPerSmallBlock];
  PixelResult r[kPixelsPerSmallBlock];
  int n = 0;
  for (int j = b[1]; j <= b[3]; ++j)
    for (int i = b[0]; i <= b[2]; ++i) p[n++] = pixel_center(img.view, img.width, img.height, i, j);
  classify_pixels(s, k, p, n, r);
  // Pixel by pixel (fill()'s memset a row is a call a pixel here).
  const std::size_t width = static_cast<std::size_t>(img.width);
  uint8_t* const labels = img.labels.data();
  uint8_t* const depth = img.depth.data();
  n = 0;
  for (int j = b[1]; j <= b[3]; ++j)
    for (int i = b[0]; i <= b[2]; ++i, ++n) {
      const std::size_t at = static_cast<std::size_t>(j) * width + static_cast<std::size_t>(i);
      labels[at] = r[n].label;
      if (s.options.depth) depth[at] = r[n].depth;
      exact += r[n].exact;
    }
  return exact;
}

// Decides one top-level block into img: whole where classify_block holds,
// else quartered. With min_block == 1 the blocks of a few pixels go to the
// CPU's per-pixel kernel (small_block) without a proof; for a device
// (min_block > 1) every block gets a proof, and the pixels of a failed one
// whose sides are at most min_block are listed. A device that shares the
// host's cores (lavapipe) classifies a listed pixel several times slower
// than the CPU's kernel, so a proof of 2 x 2 pixels pays there where it
// would not on the CPU (docs/performance.md). Returns the pixels the exact
// path decided.
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
    if (min_block == 1 && (i1 - i0 + 1) * (j1 - j0 + 1) <= kPixelsPerSmallBlock) {
      tl_pixel_reuse = {parent, &counts};
      exact += small_block(s, k, img, b);
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
  publish_pixel_lane_traversals();
  if (tl_witness_blocks) {
    witness_blocks.fetch_add(tl_witness_blocks, std::memory_order_relaxed);
    tl_witness_blocks = 0;
  }
  if (tl_unknown_blocks) {
    unknown_segment_blocks.fetch_add(tl_unknown_blocks, std::memory_order_relaxed);
    tl_unknown_blocks = 0;
  }
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

void wake_cull_workers(const RegionSetup& s, int threads) {
  const RegionRequest& o = s.options;
  if ((!o.depth && s.fixed_none) || thread_count(threads) < 2) return;  // no batch, or no worker in it
  if (o.width <= kRegionBlock && o.height <= kRegionBlock) return;    // one block: the caller's alone
  WorkerPool::shared().wake();
}

RegionImage region_cpu(const RegionSetup& s, int threads) {
  wake_cull_workers(s, threads);
  RegionImage img = blank_image(s);
  region_cull(s, img, 1, threads);
  return img;
}

}  // namespace cmr::backend
