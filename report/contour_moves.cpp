#include "report/contour_moves.hpp"

#include <algorithm>

namespace cmr::report {

bool ContourMoves::movable(int k) const { return std::binary_search(points.begin(), points.end(), k); }

bool ContourMoves::restrict(FixRequest& request) const {
  std::vector<int> kept;
  if (request.points.empty()) {
    kept = points;
  } else {
    for (int k : request.points)
      if (movable(k)) kept.push_back(k);
  }
  request.points = std::move(kept);
  request.keep = keep;
  return !request.points.empty();
}

ContourMoves contour_moves(const import::Contour& c) {
  const int m = static_cast<int>(c.font_point.size());
  const bool closed = c.spline.closed();
  // A neighbour that is a line's inner point (none beyond an open spline's ends).
  auto added = [&](int k) { return (closed || (k >= 0 && k < m)) && c.font_point[(k + m) % m] < 0; };
  ContourMoves out;
  for (int k = 0; k < m; ++k) {
    if (c.font_point[k] < 0) continue;  // a line's inner point: no source point
    const bool line_end = c.node[k] && (added(k + 1) || added(k - 1));
    if (!line_end) out.points.push_back(k);
  }
  return out;
}

}  // namespace cmr::report
