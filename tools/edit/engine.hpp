#pragma once
// The editor's one doorway into the engine: regions, verdicts, curvature
// events. Every call into region/region.hpp, bezierize/analyze.hpp and the
// report's root finding made by `cmr edit` is in engine.cpp, so an API change
// there is ported in one file.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bezierize/analyze.hpp"
#include "region/region.hpp"
#include "region/region_memo.hpp"
#include "bezierize/segments.hpp"
#include "spline/bspline.hpp"

namespace cmr::edit {

/// The label maps of one request per layer (RegionRequest, one moved point
/// each), computed on the CPU (all cores), certified: each equals `cmr region
/// FILE --point K --view ... --size WxH` for the same state.
/// With `memo`, the problems are made through it (region/region_memo.hpp:
/// the spans a move left alone are not prepared again; the same labels).
std::vector<RegionResult> compute_regions(const BSpline& spline, const std::vector<RegionRequest>& layers,
                                          RegionMemo* memo = nullptr);

/// What a region depends on, exactly: the request (view, size, mode, split,
/// depth, the moved point k and its rigid companions), the degree, knots and
/// weights,
/// the points that stay where they are, and the companions' offsets from P_k.
/// Not P_k itself: the region puts P_k (and its companions, by the same
/// vector) at every pixel centre, so wherever k's group stands the labels are
/// the same. The offsets are kept exactly (each difference of two doubles as
/// its rounded value and rounding error, an error-free transformation), so
/// equal keys mean equal exact problems and equal certified labels.
std::vector<double> region_key(const BSpline& spline, const RegionRequest& request);

/// Region layers remembered by key (most recently used first): dragging a
/// point moves only its own group, so its region is found here instead of
/// being recomputed every frame.
class RegionCache {
 public:
  explicit RegionCache(std::size_t capacity = 16) : capacity_(capacity) {}
  /// The layer for a request, or nullptr when it is not remembered.
  const RegionResult* find(const std::vector<double>& key);
  /// The layer for a request: remembered, else computed (compute_regions) and
  /// remembered, evicting the least recently used beyond the capacity.
  const RegionResult& get(const BSpline& spline, const RegionRequest& request, RegionMemo* memo = nullptr);
  /// The same with the request's key given (region_key(spline, request)).
  const RegionResult& get(const BSpline& spline, const RegionRequest& request, std::vector<double> key,
                          RegionMemo* memo = nullptr);
  /// Why the remembered layer of a request is empty or full
  /// (region_reason, region/region_reason.hpp), worked out at its first
  /// call and remembered with the layer: a frame served by the cache does not
  /// prepare the request again. nullopt when the layer is neither, when the
  /// request cannot be prepared, or when the key is not remembered.
  std::optional<std::string> reason(const BSpline& spline, const RegionRequest& request,
                                    const std::vector<double>& key, RegionMemo* memo = nullptr);
  void set_capacity(std::size_t capacity);
  std::size_t size() const { return entries_.size(); }
  /// How many reasons were worked out (not served from the cache) so far.
  long reasons_worked_out() const { return reasons_worked_out_; }

 private:
  struct Entry {
    std::vector<double> key;
    std::uint64_t hash = 0;  ///< hash(key)
    std::shared_ptr<const RegionResult> result;
    std::optional<std::optional<std::string>> reason;  ///< once worked out
  };
  Entry* entry(const std::vector<double>& key);
  long reasons_worked_out_ = 0;
  static std::uint64_t hash(const std::vector<double>& key);
  std::vector<Entry> entries_;
  std::size_t capacity_;
};

/// RGBA bytes (row-major, row 0 at the top) of the layers, in the colours of
/// `cmr region --png` (draw/draw.hpp's legend: red increasing, blue
/// decreasing, overlaps darker, optional depth shading).
std::vector<uint8_t> region_rgba(const std::vector<const RegionResult*>& layers, bool split, bool depth_shading,
                                 int max_depth);
/// The same into `rgba` (resized; its memory is reused when the size stays,
/// so an editor frame does not fault in a fresh buffer of the window's size).
void region_rgba(const std::vector<const RegionResult*>& layers, bool split, bool depth_shading, int max_depth,
                 std::vector<uint8_t>& rgba);

/// Verdicts of the spline as `cmr analyze` gives them (InputError for a split
/// joint the spline lacks).
SplineAnalysis verdicts(const BSpline& spline, int max_depth, std::optional<int> split, Mode mode,
                        std::optional<SegmentRange> segments = std::nullopt, RegionMemo* memo = nullptr);

/// Certified curvature extrema and inflections of the whole curve (as `cmr
/// report` finds them), for marking the comb and the plot.
struct CurvatureEvents {
  /// Parameters: maxima the sharpest points (maxima of |kappa|), minima the
  /// flattest, inflections the sign changes of kappa (and extrema at a joint
  /// across one); the same whichever way the curve runs.
  std::vector<double> maxima, minima, inflections;
  /// Every certified extremum of kappa as the report lists it: parameter,
  /// the extreme value of kappa, sharpest / flattest / at an inflection, and
  /// the segment it lies inside or the joint it sits on (-1 otherwise).
  struct Extremum {
    double t = 0, kappa = 0;
    int kind = 0;  ///< ExtremumKind: 0 sharpest, 1 flattest, 2 at an inflection
    int segment = -1, joint = -1;
  };
  std::vector<Extremum> extrema;
};
CurvatureEvents curvature_events(const BSpline& spline, int max_depth);

/// A knot operation by name on a copy of the spline (bezierize/knot_ops.hpp):
/// "insert" (knot a, b times, default 1), "remove" (one copy of knot a; b is
/// the absolute tolerance, default kRemovalRelativeTolerance times the
/// spline's extent), "elevate", "clamp", "uniform". Returns the new spline and
/// a status line; throws InputError when the operation does not apply (a
/// removal that would move the curve by more than the tolerance, a knot
/// outside the domain, a degree above kMaxDegree): knot_ops' message.
struct KnotResult {
  BSpline spline;
  std::string message;
};
KnotResult knot_operation(const BSpline& spline, const std::string& name, double a, double b);

}  // namespace cmr::edit
