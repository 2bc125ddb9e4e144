#pragma once
// Internal to cmr::region (region.cpp, classify_pixels): Algorithm 1 on the
// root values of one segment at up to four pixels at once, in lock step.
//
// Why. The CPU render's pixels next to a region boundary are classified one
// by one on their root values (FlatPiecesN, classify_pixel_flat): in the
// deep cells (the degree-9 zoom, the cubic zooms) most of their time is the
// halvings of the depth-first traversal, one pixel's row of n1 coefficients
// at a time. Neighbouring pixels of a small block go down nearly the same
// tree, so their rows are halved together here, one value of four pixels
// per operation (issue 39 item 4).
//
// What each pixel gets is exactly what flat_algorithm1 gives it alone, bit
// for bit. The traversal walks the union of the pixels' trees depth first;
// a pixel takes part in a node when its own traversal reaches it (every
// ancestor split for it, and it has not stopped), so it meets its own nodes
// in its own order and folds them as alone (MonotonicityFold, the same
// early stop). Each pixel's values are halved with the same operations on
// the same operands as FlatPiecesN::split (halve_in_pairs: each new value
// 0.5 (a + b), the left half in place, the right half pending), and its
// bound grows by the same expression of the same magnitude; a pixel that
// does not take part in a node is halved too (its values are unused).
// Measured (docs/performance.md, "Lock step across a small block's
// pixels"): the uniform cubic's boundary zooms 18-19 % cheaper, the
// degree-9 zoom 4-9 %, the cubic Bézier up to 6 %.
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "bezierize/classify.hpp"
#include "bezierize/decide.hpp"
#include "region/box_reuse.hpp"
#include "numeric/bounded.hpp"
#include "spline/limits.hpp"

namespace cmr::backend::detail {

inline constexpr int kPixelLanes = 4;

/// The flat per-pixel path's certain sign of a value x with its bound e
/// (region.cpp: FlatPieces, FlatPiecesN, the level-0 test; the lock step).
inline int flat_sign(double x, double e) {
  if (std::fabs(x) > e) return x > 0 ? 1 : -1;  // false for NaN: unknown
  return x == 0 && e == 0 ? 0 : kSignUnknown;
}

/// The flat path's bound e grown by the halving of a piece of n
/// coefficients whose largest magnitude is mag (one expression for
/// FlatPieces, FlatPiecesN and the lock step's lanes, T = double or a vector
/// of them; by reference, so that no vector crosses a call's ABI).
template <class T>
inline void grow_halving_bound(T& e, int n, const T& mag) {
  e += n * (0.5 * Bounded::kRound) * mag * (1 + 0x1p-20) + Bounded::kTiny;
}

// Four doubles per instruction: the lock step runs at the AVX2 level only
// (SimdLevel::avx2, chosen per process where the CPU has it; region.cpp,
// LaneResults). target("avx2") only, not FMA: each multiply and add rounds
// on its own, as in the one-pixel code.
#if defined(__x86_64__)
#define CMR_LANES_TARGET __attribute__((target("avx2")))
#else
#define CMR_LANES_TARGET
#endif

inline std::atomic<int> pixel_lanes_override{-1};
/// Whether the CPU render classifies a small block's pixels in lock step
/// (default on; the library reads no environment: tools/ read
/// CMR_PIXEL_LANES into set_pixel_lanes). Labels and depths are the same
/// either way.
inline bool pixel_lanes() { return pixel_lanes_override.load(std::memory_order_relaxed) != 0; }
inline void set_pixel_lanes(int on) { pixel_lanes_override.store(on, std::memory_order_relaxed); }
/// Pixel traversals run in lock step since the process started (tests: so
/// that a comparison cannot pass vacuously). Each thread counts its own
/// (count_pixel_lane_traversals) and adds them here once per block job
/// (publish_pixel_lane_traversals, block.cpp), as the SIMD pixel counts
/// are: one shared add per block job instead of one per traversal (no
/// difference measured on the 2-core VM; it keeps the render's threads off
/// one shared cache line).
inline std::atomic<std::uint64_t> pixel_lane_traversals{0};
inline thread_local std::uint64_t tl_pixel_lane_traversals = 0;
inline void count_pixel_lane_traversals(int lanes) { tl_pixel_lane_traversals += static_cast<std::uint64_t>(lanes); }
inline void publish_pixel_lane_traversals() {
  if (tl_pixel_lane_traversals == 0) return;
  pixel_lane_traversals.fetch_add(tl_pixel_lane_traversals, std::memory_order_relaxed);
  tl_pixel_lane_traversals = 0;
}

using PixelLaneValues = double __attribute__((vector_size(8 * kPixelLanes)));

/// FlatPiecesN<N>::split at every lane: the bound e grows by the same
/// expression of the same magnitude (max |cur_k|, as std::max folds it, NaN
/// included), and cur is halved as halve_in_pairs<N> halves one row (each
/// new value 0.5 (a + b); after row r, value 0 is the left half's r and
/// value m - 1 the right half's m - 1, m = N - r), the left half in cur, the
/// right half in right. Test: PixelLanes.SplitIsFlatPiecesSplitBitForBit.
template <int N>
CMR_LANES_TARGET inline void split_lanes(PixelLaneValues* cur, PixelLaneValues& e, PixelLaneValues* right) {
  PixelLaneValues mag{};
  for (int k = 0; k < N; ++k) {
    const PixelLaneValues a = cur[k] < 0 ? -cur[k] : cur[k];
    mag = mag < a ? a : mag;
  }
  grow_halving_bound(e, N, mag);
  PixelLaneValues w[N];
  for (int k = 0; k < N; ++k) w[k] = cur[k];
  right[N - 1] = cur[N - 1];
  for (int r = 1; r < N; ++r) {
    const int m = N - r;
    for (int k = 0; k < m; ++k) w[k] = 0.5 * (w[k] + w[k + 1]);
    cur[r] = w[0];
    right[m - 1] = w[m - 1];
  }
}

/// Algorithm 1 of one segment at `lanes` (1..kPixelLanes) pixels: coefficient
/// k of pixel l's root values at v[k * stride + pixel[l]], e[l] their one
/// bound. out[l]: as flat_algorithm1 (no block record) gives that pixel
/// alone, nullopt where a sign is not certain with the flat bound.
/// With `record` (the failed block proof around these pixels, the same for
/// all: box_reuse.hpp), its facts replace the nodes' own rules as in
/// traverse_with_record, and `reused` counts them per pixel as there.
template <int N>
CMR_LANES_TARGET void flat_algorithm1_lanes(const double* v, std::size_t stride, const int* pixel, const double* e, int lanes, int D,
                           const SegmentRecord* record, std::uint64_t* reused,
                           std::optional<MonotonicityResult>* out) {
  using Lanes = PixelLaneValues;
  static_assert(N >= 2);
  // cur[k]: coefficient k of the current piece at each pixel; pending[level][k]:
  // the right half waiting at that level (FlatPiecesN's cur_ and pending_).
  struct State {
    Lanes cur[N];
    Lanes pending[kMaxDepth + 1][N];
    Lanes e, pending_e[kMaxDepth + 1];
  };
  static thread_local State st;
  for (int k = 0; k < N; ++k)
    for (int l = 0; l < kPixelLanes; ++l) st.cur[k][l] = v[k * stride + static_cast<std::size_t>(pixel[l < lanes ? l : 0])];
  for (int l = 0; l < kPixelLanes; ++l) st.e[l] = e[l < lanes ? l : 0];

  // One pixel's current piece as FlatPiecesN shows it to scan_signs.
  struct View {
    const State& s;
    int l;
    int size() const { return N; }
    int sign(int k) const { return flat_sign(s.cur[k][l], s.e[l]); }
  };
  MonotonicityFold fold[kPixelLanes];
  bool certain[kPixelLanes];
  unsigned live = (1u << lanes) - 1;  // pixels whose traversal goes on
  for (int l = 0; l < kPixelLanes; ++l) certain[l] = true;
  unsigned part[kMaxDepth + 2];  // pixels whose traversal reaches the nodes of each level's current parent
  part[0] = live;
  RecordReader reader(record);
  int level = 0, j = 0;
  for (;;) {
    unsigned split = 0;
    // The record's fact at this node, asked once for all (in preorder, as
    // each pixel alone would ask it).
    const NodeFact fact = record && (part[level] & live) ? reader.at(level, j) : NodeFact::none;
    for (int l = 0; l < lanes; ++l) {
      if (!((part[level] & live) >> l & 1u)) continue;
      Piece p;
      if (fact != NodeFact::none) {
        if (reused) ++*reused;
        p = fact_piece(fact);
      } else {
        View view{st, l};
        p = monotonicity_piece(scan_signs(view, false));
      }
      if (p == Piece::uncertain) {
        certain[l] = false;
        live &= ~(1u << l);
      } else if (p == Piece::split && level < D) {
        split |= 1u << l;
      } else if (fold[l].visit(p, level)) {
        live &= ~(1u << l);
      }
    }
    if (split) {  // FlatPiecesN::split at every pixel
      ++level;
      j *= 2;
      part[level] = split;
      split_lanes<N>(st.cur, st.e, st.pending[level]);
      st.pending_e[level] = st.e;
      continue;
    }
    if (!live) break;
    // Climb while on a right child, then go to the right sibling.
    while (level > 0 && (j & 1) == 1) {
      --level;
      j >>= 1;
    }
    if (level == 0) break;
    ++j;
    for (int k = 0; k < N; ++k) st.cur[k] = st.pending[level][k];
    st.e = st.pending_e[level];
  }
  for (int l = 0; l < lanes; ++l) out[l] = certain[l] ? std::optional(fold[l].result(D)) : std::nullopt;
}

}  // namespace cmr::backend::detail
