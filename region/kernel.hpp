#pragma once
// Internal to cmr::region: the parts of the CPU backend's pixel kernel
// (region.cpp) that the setup (setup.cpp) and the block proofs (block.cpp)
// share. Not for users of the library (they include region/region.hpp) nor
// for backends (region/region_setup.hpp).
#include <cstdint>
#include <optional>
#include <vector>

#include "bezierize/decide.hpp"
#include "numeric/halve_bounded.hpp"
#include "numeric/poly3.hpp"
#include "region/box_eval.hpp"
#include "region/box_reuse.hpp"
#include "region/pixel_simd.hpp"
#include "region/region_setup.hpp"

namespace cmr::backend::detail {

using box_eval::eval_poly;
using box_eval::Monomials;

// q 2^-e, exactly (setup.cpp).
Rational scaled(Rational q, int e);

// The label from the verdict template with the entries' classes and the
// varying jumps filled in (region.cpp).
PixelResult verdict(const RegionSetup& s, const std::vector<SegmentClass>& classes, const std::vector<Joint>& joints,
                    bool exact);

// Whether the label is 0 whatever the classes of the entries marked unknown
// (unknown[q] & 1: its monotonicity, & 2: its inflection) and whatever the
// jumps of the joints that vary with the position (region.cpp): some group's
// part_verdict is "none" with those classes read as nothing and those jumps
// as 0. `classes` holds the template filled in for the other entries; the
// unknown parts are overwritten.
bool fails_whatever_unknown(const RegionSetup& s, std::vector<SegmentClass>& classes,
                            const std::vector<char>& unknown);

// The curvature jumps of the joints whose jump depends on the position, for
// displacements enclosed by (bx, by) (region.cpp). False when a sign is not
// certain there.
bool varying_jumps(const RegionSetup& s, Bounded bx, Bounded by, std::vector<Joint>& joints);

// The certified fast path for a point or a box of displacements (region.cpp).
std::optional<PixelResult> classify_fast(const RegionSetup& s, const Monomials& mono, Bounded bx, Bounded by);

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
      : e_(e), m_(m), levels_(levels), eta_(eta), n1_(eta ? e.n_nu : e.n_xi), simd_(simd_level()) {
    static thread_local std::vector<double> scratch;
    static thread_local std::vector<Bounded> inner;
    const std::size_t need = static_cast<std::size_t>(2 * (kMaxDepth + 3)) * n1_;
    if (scratch.size() < need) scratch.resize(need);
    if (inner.size() < static_cast<std::size_t>(n1_)) inner.resize(static_cast<std::size_t>(n1_));
    base_ = scratch.data();
    inner_ = inner.data();
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
      pend_[level].p.last = last_;
      pend_[level].p.has_last = has_last_;
      pend_[level].p.has_first = false;  // set when the left half's last is evaluated
      has_last_ = false;
    }
    select(level, j);
  }
  void next(int level, int j) {
    if (level > levels_) {
      std::copy(slot(level), slot(level) + 2 * n1_, cur());
    } else {
      const Pending& q = pend_[level].p;
      first_ = q.first;
      has_first_ = q.has_first;
      last_ = q.last;
      has_last_ = q.has_last;
    }
    select(level, j);
  }

 private:
  void select(int level, int j) {
    level_ = level;
    j_ = j;
    if (level <= levels_) piece_ = (1 << level) - 1 + j;
    inner_groups_ = 0;
  }
  // A piece: n1 values, then their n1 bounds.
  double* cur() const { return base_; }
  double* work() const { return base_ + 2 * n1_; }
  double* slot(int level) const { return base_ + static_cast<std::size_t>(2 * (level + 2)) * n1_; }
  Bounded coeff(int k) const {
    if (level_ > levels_) return {cur()[k], cur()[n1_ + k]};
    if (k == 0 && has_first_) return first_;
    if (k == n1_ - 1 && has_last_) return last_;
    const Bounded b = k == 0 || k == n1_ - 1 ? from_poly(k) : from_group(k);
    if (k == 0) {
      first_ = b;
      has_first_ = true;
    }
    if (k == n1_ - 1) {
      last_ = b;
      has_last_ = true;
      if (level_ > 0 && (j_ & 1) == 0) {  // a left half: its last is its pending sibling's first
        pend_[level_].p.first = b;
        pend_[level_].p.has_first = true;
      }
    }
    return b;
  }
  Bounded from_poly(int k) const {
    const std::size_t at = static_cast<std::size_t>(piece_) * n1_ + k;
    return eta_ ? eval_poly(e_.nu[at], m_) : eval_poly(e_.xi[at], m_);
  }
  // An inner coefficient of xi over a box: it and the others of its group of
  // four (coefficients 1-4, 5-8, ...) are evaluated together (eval_polys:
  // one instruction for the four at the AVX2 level, bit for bit eval_poly's
  // values), since a scan that reads one inner coefficient mostly reads its
  // neighbours too.
  Bounded from_group(int k) const {
    const int g = (k - 1) / 4;
    if (eta_ || m_.point || g >= 64) return from_poly(k);
    if (!(inner_groups_ >> g & 1)) {
      const int first = 1 + 4 * g, count = std::min(4, n1_ - 1 - first);
      const std::array<double, kPoly3Terms>* rows[4];
      for (int i = 0; i < count; ++i) rows[i] = &e_.xi[static_cast<std::size_t>(piece_) * n1_ + first + i];
      box_eval::eval_polys(simd_, rows, count, m_, inner_ + first);
      inner_groups_ |= std::uint64_t{1} << g;
    }
    return inner_[k];
  }
  const RegionEntry& e_;
  const Monomials& m_;
  int levels_;
  bool eta_;
  int n1_;
  SimdLevel simd_;  // eval_polys' level for the groups of inner coefficients
  int level_ = 0, j_ = 0, piece_ = 0;
  double* base_;  // current piece, work space, then one pending slot per level 1..kMaxDepth
  // The current piece's inner coefficients evaluated so far, in groups of
  // four (bit g: coefficients 4g + 1 to 4g + 4), down to the precomputed levels.
  Bounded* inner_;
  mutable std::uint64_t inner_groups_ = 0;
  // The current piece's end values once known (down to the precomputed
  // levels), and per level those of the pending right half. The per-level
  // slots are left uninitialised: split(level) writes a level's slots before
  // next(level) reads them (the traversal splits a piece before it visits
  // the right half), and zeroing them cost every block proof and every
  // pixel's eta traversal about a kilobyte of stores (a sixth of
  // box_traversal's own time).
  struct Pending {
    Bounded first, last;
    bool has_first, has_last;
  };
  union PendingSlot {
    PendingSlot() {}  // no member initialised
    Pending p;
  };
  mutable Bounded first_{}, last_{};
  mutable bool has_first_ = false, has_last_ = false;
  mutable PendingSlot pend_[kMaxDepth + 1];
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

// What the failed block around the current pixels learned (cull_block sets
// it around small_block on its thread; null: nothing known), and where the
// pixels count their reuse. Labels only (box_reuse.hpp).
struct PixelReuse {
  const BoxKnowledge* known = nullptr;
  BlockReuseCounts* counts = nullptr;
};
extern thread_local PixelReuse tl_pixel_reuse;  // region.cpp

// Pixels of the CPU render through the kernel, with their fallbacks
// (region.cpp). Writes out[0..count).
void classify_pixels(const RegionSetup& s, const PixelKernel& k, const Vec2* p, int count, PixelResult* out);

}  // namespace cmr::backend::detail
