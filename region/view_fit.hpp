#pragma once
// Internal to cmr::region and the libraries above it: a library user includes
// `region/region.hpp` (space curves: `region/space_region.hpp`).
/// A region picture's default view that shows the answer (issue 40 item 6),
/// one rule for `cmr region` (planar: fit_region_view; a space curve: the
/// report's thumbnails too), and `cmr sweep` (every step): a square probe
/// three times the polygon's view about its centre is rendered small; the
/// box of its region pixels and of the moved points, widened by 15% of its
/// larger side each way and then in one direction so that the picture's
/// pixels are square, is the view.
#include <limits>
#include <vector>

#include "region/region.hpp"

namespace cmr {

class ViewFit {
 public:
  /// The probe's view: square, about `polygon`'s centre, three times its larger side.
  static View probe_view(const View& polygon);

  /// Adds the rectangles of `probe`'s region pixels (RegionResult::in_region),
  /// a picture rendered over `view`; returns how many there were.
  int add_region(const RegionResult& probe, const View& view);
  /// Adds a point (the moved control point, in the picture's coordinates).
  void add_point(double x, double y);
  /// Adds a planar request's moved points (its point and its --with points)
  /// as they are in `spline` (indices out of range are skipped:
  /// RegionProblem::make names them).
  void add_moved_points(const BSpline& spline, const RegionRequest& request);

  /// No region pixel was added.
  bool empty() const { return pixels_ == 0; }
  /// The box with its margin, widened to width x height square pixels.
  View view(int width, int height) const;

 private:
  int pixels_ = 0;
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  double x0_ = kInf, y0_ = kInf, x1_ = -kInf, y1_ = -kInf;
};

/// The default view of a planar `cmr region` (the Python module's region()
/// too): the union of the regions of `requests` (one per moved point, their
/// views ignored; `cmr region --point all` gives several) and of their moved
/// points, fitted by ViewFit. Each request is probed on the CPU at `probe`
/// x `probe` pixels over ViewFit::probe_view of the polygon's view
/// (default_view for the requests' size, which all share), and where that
/// finds no region pixel, again over the square of the polygon's view's
/// larger side (a third of the first probe: pixels 3 times finer, for
/// regions smaller than the first probe's pixels). No region pixel in
/// either: the polygon's view, `empty`; every pixel of every probe in
/// the region (nothing to frame: a point that acts on no judged segment):
/// the polygon's view too, `full`. Throws InputError as RegionProblem::make
/// does for a bad request.
struct RegionViewFit {
  View view;
  bool empty = true;              ///< no region pixel in any probe: `view` is the polygon's
  bool full = false;              ///< every probe pixel in the region: `view` is the polygon's
  bool fitted() const { return !empty && !full; }
  std::vector<int> probe_pixels;  ///< each request's region pixels in its (last) probe
  int probe = 0;                  ///< the probe's side in pixels
};
inline constexpr int kRegionProbeSize = 64;
RegionViewFit fit_region_view(const BSpline& spline, const std::vector<RegionRequest>& requests,
                              int probe = kRegionProbeSize);

}  // namespace cmr
