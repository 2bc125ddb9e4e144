#pragma once
/// A region picture's default view that shows the answer (issue 40 item 6),
/// one rule for `cmr sweep` (planar, every step) and a space region (the
/// report's thumbnails, `cmr region` of a space curve): a square probe three
/// times the polygon's view about its centre is rendered small; the box of
/// its region pixels and of the moved points, widened by 15% of its larger
/// side each way and then in one direction so that the picture's pixels are
/// square, is the view.
#include <limits>

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

  /// No region pixel was added.
  bool empty() const { return pixels_ == 0; }
  /// The box with its margin, widened to width x height square pixels.
  View view(int width, int height) const;

 private:
  int pixels_ = 0;
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  double x0_ = kInf, y0_ = kInf, x1_ = -kInf, y1_ = -kInf;
};

}  // namespace cmr
