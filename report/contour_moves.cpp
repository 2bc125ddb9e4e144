#include "report/contour_moves.hpp"

#include <algorithm>

#include "spline/fields.hpp"

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

std::vector<std::string> named_points(const import::Glyph& g, const std::vector<std::string>& items) {
  std::vector<std::string> out;
  for (const std::string& item : items) {
    const auto tail_of = [&](const std::string& name) {
      return name == item || (name.size() > item.size() && name.compare(name.size() - item.size(), item.size(), item) == 0 &&
                              name[name.size() - item.size() - 1] == '/');
    };
    const import::Contour* found = nullptr;
    int at = -1, matches = 0;
    for (const import::Contour& c : g.contours)
      for (std::size_t k = 0; k < c.point_names.size(); ++k) {
        const int sp = k < c.source_point.size() ? c.source_point[k] : -1;
        const bool labelled = c.font_point[k] >= 0 && c.index < static_cast<int>(g.point_labels.size()) && sp >= 0 &&
                              sp < static_cast<int>(g.point_labels[c.index].size()) && g.point_labels[c.index][sp] == item;
        if (!item.empty() && (tail_of(c.point_names[k]) || labelled)) found = &c, at = static_cast<int>(k), ++matches;
      }
    if (matches == 0)
      throw InputFieldError(field("points") + ": '" + item + "' names no point of the glyph " + g.name + " (names as " +
                            g.name + "/c0/p3, c0/p3 or p3)");
    if (matches > 1)
      throw InputFieldError(field("points") + ": '" + item + "' names " + std::to_string(matches) +
                            " points (give the whole name)");
    const std::string& name = found->point_names[at];
    if (found->font_point[at] < 0)
      throw InputFieldError(field("points") + ": " + name +
                            " is a line's inner point, no point of the source (a line stays a line)");
    if (!contour_moves(*found).movable(at))
      throw InputFieldError(field("points") + ": " + name +
                            " ends a straight line, so it stays where it is (a line stays a line)");
    out.push_back(name);
  }
  return out;
}

}  // namespace cmr::report
