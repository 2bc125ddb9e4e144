#pragma once
// Internal to cmr::region and the libraries above it: a library user includes
// `region/region.hpp` (space curves: `region/space_region.hpp`).
/// Reuse of a failed block proof by the block's quarters and pixels (region
/// CPU backend, labels only; block.cpp: classify_box_labels, cull_block;
/// region.cpp: classify_pixel_flat). Switch: CMR_BLOCK_REUSE=0 in cmr's environment (or
/// set_block_reuse) turns it off; labels are the same either way.
///
/// What a block proof learns. The box traversal (block_piece's rules over the
/// displacements of a box of pixels) certifies signs of exact coefficients at
/// EVERY displacement of the box. A node's fact is recorded when it holds for
/// every sub-box and every pixel, whatever their own rounding:
///   increasing / decreasing: every coefficient of the piece is certainly
///     >= 0 (<= 0), not all zero (for eta: certainly > 0 (< 0)); or the
///     node's subtree was traversed completely and every leaf below it is of
///     that one direction ("uniform");
///   split: both ends certainly of one non-zero sign or a structural zero
///     (Algorithm 1: xi_0 xi_n < 0 certainly false) and a coefficient
///     certainly > 0 and one certainly < 0 (for eta: ends certainly alike and
///     non-zero, some coefficient certainly <= 0 and some certainly >= 0).
/// Other nodes record nothing (their outcome may change with the box).
///
/// Why every pixel's label is unchanged. Let N be a node with a recorded
/// fact and p any displacement in the box (a pixel or a point of a sub-box).
///  * split: at p the exact signs give, by the tables of decide.hpp, rule (3)
///    false, rules (1), (2) false (both signs present): Algorithm 1 splits N
///    (Algorithm 2 likewise), and so does block_piece for any sub-box.
///  * a leaf direction: at p all coefficients of N are >= 0 with one > 0,
///    so Algorithm 1 decides N `increasing` (block_piece for a sub-box too).
///  * uniform (a complete subtree whose box leaves all have one direction,
///    say increasing): the traversal at p may decide a node M of N's subtree
///    above the box leaves, but M's end coefficients are end coefficients of
///    box leaves below it (subdivision keeps the ends), all >= 0, so rule (3)
///    cannot fire at M; M's polynomial is > 0 somewhere (a leaf below has
///    non-negative coefficients, one positive), so M is not `decreasing` nor
///    `zero`. Every decided node of N's subtree is thus `increasing` and no
///    node is split at level D (box leaves are at levels <= D). Folding them
///    (MonotonicityFold, InflectionFold, BoxFold) gives the same answer as
///    one `increasing` leaf at N in the same place of the order: only the
///    depth can differ, and these facts are used only without a depth map.
/// A node's fact is only used when the traversal at p (or of the sub-box)
/// reaches that node. If it decides an ancestor first (e.g. "not monotone"
/// by rule 3 at an ancestor), it never asks, and its outcome is its own
/// exact one. So the sequence of decisions a traversal folds is Algorithm 1's
/// (2's) on the exact coefficients wherever its own signs are certain, and
/// the facts replace only evaluations whose exact outcome they state: the
/// flat pixel path, which otherwise gives Algorithm 1's answer or gives up,
/// still does; a sub-box proof stays a proof. A segment whose root is uniform
/// over the parent box is not traversed again at all. The parent's
/// "level 0 does not fail" (ends certainly not opposite over the box) also
/// holds for every sub-box; "level 0 is unknown" is not inherited.
#include <atomic>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "bezierize/decide.hpp"
#include "spline/limits.hpp"

namespace cmr::backend {

enum class NodeFact : std::uint8_t { increasing, decreasing, split, none };

inline std::atomic<int> block_reuse_override{-1};
/// Whether a block proof's subdivision is reused (default on; the library
/// reads no environment: tools/ read CMR_BLOCK_REUSE into set_block_reuse).
inline bool block_reuse() { return block_reuse_override.load(std::memory_order_relaxed) != 0; }
/// Turns reuse off (0) or on (1; -1: the default, on) for later renders
/// (tests, benchmarks, tools/cli_common.hpp read_environment).
inline void set_block_reuse(int on) { block_reuse_override.store(on, std::memory_order_relaxed); }

inline std::atomic<int> witness_override{-1};
/// Whether a failed block proof searches for a not-monotone witness
/// (block.cpp, not_monotone_witness; default on; tests turn it off to
/// compare). Labels are the same either way.
inline bool witness_search() { return witness_override.load(std::memory_order_relaxed) != 0; }
inline void set_witness_search(int on) { witness_override.store(on, std::memory_order_relaxed); }
/// Blocks a witness decided since the process started (tests: so that a
/// comparison cannot pass vacuously), added once per block job.
inline std::atomic<std::uint64_t> witness_blocks{0};
/// Blocks labelled 0 with a segment left unresolved, because the others fail
/// whatever it does (block.cpp, fails_whatever_unknown), since the process
/// started (tests), added once per block job.
inline std::atomic<std::uint64_t> unknown_segment_blocks{0};

/// How often reuse happened since the process started (tests: so that a
/// comparison cannot pass vacuously).
struct BlockReuseCounts {
  std::uint64_t box_nodes = 0;     ///< nodes a sub-box took from its parent without evaluating
  std::uint64_t box_segments = 0;  ///< segment traversals a sub-box skipped (uniform over the parent)
  std::uint64_t box_level0 = 0;    ///< level-0 checks a sub-box skipped
  std::uint64_t pixel_nodes = 0;   ///< nodes a pixel took from its block
  std::uint64_t pixel_segments = 0;  ///< segment traversals a pixel skipped
  std::uint64_t eta = 0;  ///< of all these, the nodes and segments of Algorithm 2 (nu; CMR mode)
};
inline std::atomic<std::uint64_t> block_reuse_totals[6];
inline BlockReuseCounts block_reuse_counts() {
  const auto at = [](int i) { return block_reuse_totals[i].load(std::memory_order_relaxed); };
  return {at(0), at(1), at(2), at(3), at(4), at(5)};
}
inline void add_block_reuse_counts(const BlockReuseCounts& c) {
  const std::uint64_t v[6] = {c.box_nodes, c.box_segments, c.box_level0, c.pixel_nodes, c.pixel_segments, c.eta};
  for (int i = 0; i < 6; ++i)
    if (v[i]) block_reuse_totals[i].fetch_add(v[i], std::memory_order_relaxed);
}

/// The recorded nodes of one traversal, in depth-first (pre)order.
struct SegmentRecord {
  struct Node {
    std::uint64_t key;
    NodeFact fact;
  };
  std::vector<Node> nodes;
  bool level0_no = false;  ///< the whole segment's ends certainly not opposite over the box
  /// A search for a not-monotone witness over the box (block.cpp,
  /// not_monotone_witness) showed that none in a sub-box can go beyond the
  /// sub-box's level-0 test: the quarters skip their own search (a skipped
  /// search never changes a label, it only leaves a block to its quarters
  /// and pixels).
  bool no_witness = false;
  void clear() {
    nodes.clear();
    level0_no = false;
    no_witness = false;
  }
  /// The direction of the whole segment when its root is uniform.
  NodeFact whole() const {
    if (nodes.empty() || nodes[0].key != key(0, 0)) return NodeFact::none;
    const NodeFact f = nodes[0].fact;
    return f == NodeFact::increasing || f == NodeFact::decreasing ? f : NodeFact::none;
  }
  /// Preorder key: (start of the node's interval in units of 2^-kMaxDepth, level).
  static std::uint64_t key(int level, int j) {
    return ((static_cast<std::uint64_t>(j) << (kMaxDepth - level)) << 5) | static_cast<std::uint64_t>(level);
  }
};

/// What a failed block proof hands to its quarters and pixels: one record
/// per region entry for xi (Algorithm 1) and for nu (Algorithm 2).
struct BoxKnowledge {
  std::vector<SegmentRecord> xi, nu;
  /// The proof left one entry unresolved and the others, all resolved, do
  /// not fail whatever it does (block.cpp, fails_whatever_unknown): in a
  /// sub-box they keep their directions, so the sub-box's proof stops at an
  /// unresolved entry instead of classifying the others (a guess that saves
  /// their traversals; stopping never changes a label).
  bool others_decide_nothing = false;
  void reset(std::size_t entries) {
    xi.resize(entries);
    nu.resize(entries);
    for (auto& r : xi) r.clear();
    for (auto& r : nu) r.clear();
    others_decide_nothing = false;
  }
};

inline Piece fact_piece(NodeFact f) {
  switch (f) {
    case NodeFact::increasing: return Piece::increasing;
    case NodeFact::decreasing: return Piece::decreasing;
    case NodeFact::split: return Piece::split;
    default: return Piece::uncertain;
  }
}

/// A reader of a parent's record, for a traversal in the same (pre)order:
/// the fact of each node asked, or none.
class RecordReader {
 public:
  explicit RecordReader(const SegmentRecord* r) : r_(r) {}
  NodeFact at(int level, int j) {
    if (!r_) return NodeFact::none;
    const std::uint64_t k = SegmentRecord::key(level, j);
    while (at_ < r_->nodes.size() && r_->nodes[at_].key < k) ++at_;
    return at_ < r_->nodes.size() && r_->nodes[at_].key == k ? r_->nodes[at_].fact : NodeFact::none;
  }

 private:
  const SegmentRecord* r_;
  std::size_t at_ = 0;
};

/// The fact a box traversal learned at one node from its summary and block_piece's outcome.
inline NodeFact box_fact(const SignSummary& s, Piece p, bool eta) {
  if (p == Piece::increasing) return NodeFact::increasing;
  if (p == Piece::decreasing) return NodeFact::decreasing;
  if (p != Piece::split) return NodeFact::none;
  if (eta)
    return ends_touch(s.first, s.last) == Truth::no && s.neg + s.zero > 0 && s.pos + s.zero > 0 ? NodeFact::split
                                                                                                : NodeFact::none;
  return ends_opposite(s.first, s.last) == Truth::no && s.pos > 0 && s.neg > 0 ? NodeFact::split : NodeFact::none;
}

/// Writes a traversal's record: every decided node in preorder; a node
/// whose subtree completes with every entry below it of one direction
/// becomes a uniform node of that direction (its entries below are dropped).
class RecordWriter {
 public:
  explicit RecordWriter(SegmentRecord* r) : r_(r) {}
  void node(int level, int j, NodeFact f) {
    if (!r_) return;
    path_[level] = r_->nodes.size();
    r_->nodes.push_back({SegmentRecord::key(level, j), f});
  }
  void done(int level) {
    if (!r_) return;
    const std::size_t i = path_[level];
    std::vector<SegmentRecord::Node>& n = r_->nodes;
    if (n[i].fact == NodeFact::increasing || n[i].fact == NodeFact::decreasing) return;
    if (n.size() == i + 1) return;  // split at level D: nothing below
    const NodeFact d = n[i + 1].fact;
    if (d != NodeFact::increasing && d != NodeFact::decreasing) return;
    for (std::size_t k = i + 2; k < n.size(); ++k)
      if (n[k].fact != d) return;
    n.resize(i + 1);
    n[i].fact = d;
  }

 private:
  SegmentRecord* r_;
  std::size_t path_[kMaxDepth + 1] = {};
};

/// A pixel traversal (rule: monotonicity_piece or inflection_piece) that
/// takes the facts of its block's record where it reaches them.
template <class Source, class Rule, class Visit>
bool traverse_with_record(Source& src, int max_depth, Rule rule, Visit visit, const SegmentRecord* record,
                          std::uint64_t& reused) {
  RecordReader reader(record);
  return traverse_nodes(
      src, max_depth,
      [&](int level, int j) {
        const NodeFact f = reader.at(level, j);
        if (f != NodeFact::none) {
          ++reused;
          return fact_piece(f);
        }
        return rule(scan_signs(src));
      },
      visit, [](int) {});
}

}  // namespace cmr::backend
