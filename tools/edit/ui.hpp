#pragma once
// The editor's Dear ImGui layer: the overlay on the region (curve, control
// polygon, points, curvature comb with certified extrema and inflections)
// and the panels (controls, knot ruler, verdicts, curvature plot). Buttons
// call the same Editor actions the script does.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "tools/edit/editor.hpp"

namespace cmr::edit {

/// Where the knot ruler was drawn (window pixels): scripts drag its handles
/// with the pointer, as a user does.
struct KnotRulerGeometry {
  float x0 = 0, width = 0;                  ///< x of the first and span of the ruler
  double lo = 0, hi = 1;                    ///< knot values at its ends
  std::vector<std::array<float, 2>> handles;  ///< centre of knot i's handle
  bool shown = false;
  /// The x at which a handle stands for knot value u.
  float x_of(double u) const { return x0 + static_cast<float>((u - lo) / (hi - lo)) * width; }
};

struct UiInfo {
  std::string region_path;  ///< RegionPainter::describe()
  double frame_ms = 0;      ///< last frame time
  bool* export_png = nullptr;  ///< set when the user asks for a PNG of the view
  KnotRulerGeometry* ruler = nullptr;  ///< filled with the knot ruler's place
  /// Filled with the typed fields' rectangles (x0, y0, x1, y1; "x", "y",
  /// "w"): scripts click into them and type, as a user does.
  std::map<std::string, std::array<float, 4>>* fields = nullptr;
};

/// Builds this frame's ImGui content (between ImGui::NewFrame and Render).
void build_ui(Editor& editor, const UiInfo& info);

}  // namespace cmr::edit
