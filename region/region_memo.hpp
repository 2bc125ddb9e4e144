#pragma once
// Internal to cmr::region and the libraries above it: a library user includes
// `region/region.hpp` (space curves: `region/space_region.hpp`).
// Locality of region setup (issue 23, item 4): a point's move changes the
// Bezier points of the d+1 spans it acts on and nothing else, so between two
// region problems of a spline that differ by a moved point (an editor's drag,
// a sweep's step) everything prepared per span can be reused.
//
// RegionMemo remembers, by each span's exact data (its index, its window of
// 2d knots, d+1 control points and weights, and the options that shape the
// result), the per-span work of a region setup:
//  - analyze's segment_shape and classify_segment (Algorithms 1 and 2 on the
//    spans the move leaves alone: the fixed classes and their lambda/eta
//    decisions) and joint_between (their curvature jumps);
//  - prepare_region's entries (the moved Bezier points and the exact piece
//    polynomials of the spans the moved group touches).
// Equal keys mean the same exact inputs to the same deterministic functions,
// so a problem made through the memo is the problem RegionProblem::make
// gives: the same certified label at every position (tests/bezierize/
// region_memo_test.cpp compares label maps).
//
// Between two calls on splines of the same knots that differ in a few control
// points (an editor's frame after a move), make() does not look at the other
// spans at all: it finds the moved points (one bitwise comparison of the
// point and weight arrays), and patches the kept base of that depth in place
// (when no problem still holds it; a copy otherwise) at the d+1 spans of each
// moved point and their joints. The base's whole-spline verdicts (cmrwi,
// cmr, cmr_algorithm2, joint_conflicts) are kept exact by a tree of
// part_verdict's run summaries (O(log N) per patched span). analyze() reads
// its per-span results from the same kept base (with the default continuity
// tolerances; other tolerances look every span up by its data). What stays
// O(N) per call is that comparison, one copy of the spline's arrays (memcpy
// speed, no per-span work) and prepare_region's flag passes; analyze() also
// folds its verdicts over the judged range. Counts says how many spans were
// touched.
//
// Not thread-safe: one memo per thread (the editor, a sweep).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "bezierize/analyze.hpp"
#include "region/region.hpp"

namespace cmr {

namespace backend {
struct RegionBase;
struct RegionEntry;
}  // namespace backend

class RegionMemo {
 public:
  RegionMemo();
  ~RegionMemo();
  RegionMemo(const RegionMemo&) = delete;
  RegionMemo& operator=(const RegionMemo&) = delete;

  /// analyze(spline, options), its per-span work remembered.
  SplineAnalysis analyze(const BSpline& spline, const AnalyzeOptions& options);
  /// RegionProblem::make(spline, request) (the same validation and errors),
  /// its per-span work remembered.
  RegionProblem make(const BSpline& spline, const RegionRequest& request);

  /// What was computed and what reused since the memo was made (spans:
  /// shapes, classes and joints; entries: the moved spans' preparations).
  /// bases_built: bases analysed over every span (the first call, new knots,
  /// degree or depth); bases_patched: bases made from the last one by
  /// patching spans_patched spans in place; bases_copied: of those, the ones
  /// that had to copy the last base first (a problem still held it).
  struct Counts {
    long spans_computed = 0, spans_reused = 0, entries_computed = 0, entries_reused = 0;
    long bases_built = 0, bases_patched = 0, bases_copied = 0, spans_patched = 0;
  };
  const Counts& counts() const { return counts_; }
  /// Entries kept at most, over every kind (the least recently used go first).
  static constexpr std::size_t kMinCapacity = 4096;

 private:
  struct KeyHash {
    std::size_t operator()(const std::vector<std::uint64_t>& k) const noexcept;
  };
  template <class V>
  struct Slot {
    V value;
    long used = 0;
  };
  template <class V>
  using Map = std::unordered_map<std::vector<std::uint64_t>, Slot<V>, KeyHash>;
  AnalyzeParts parts();
  /// Drops what was not used in the last few calls once the memo is large.
  void trim(std::size_t spans);
  std::shared_ptr<const backend::RegionBase> base(const BSpline& spline, int max_depth);
  /// The last base's whole-spline verdict summaries (region_memo.cpp).
  struct Whole;

  Map<SegmentShape> shapes_;
  Map<SegmentClass> classes_;
  Map<Joint> joints_;
  Map<std::shared_ptr<const backend::RegionEntry>> entries_;
  /// The bases kept (one per depth, the last kBaseSlots depths used): not
  /// const, patched in place when the memo is their only holder.
  struct BaseSlot {
    std::shared_ptr<backend::RegionBase> base;
    std::unique_ptr<Whole> whole;
    long used = 0;
  };
  static constexpr std::size_t kBaseSlots = 3;
  std::vector<BaseSlot> bases_;
  long call_ = 0;
  Counts counts_;
};

}  // namespace cmr
