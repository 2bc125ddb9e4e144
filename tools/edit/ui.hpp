#pragma once
// The editor's Dear ImGui layer: the overlay on the region (curve, control
// polygon, points, curvature comb with certified extrema and inflections)
// and the panels (controls, knot ruler, verdicts, curvature plot). Buttons
// call the same Editor actions the script does.
#include <string>

#include "tools/edit/editor.hpp"

namespace cmr::edit {

struct UiInfo {
  std::string region_path;  ///< RegionPainter::describe()
  double frame_ms = 0;      ///< last frame time
  bool* export_png = nullptr;  ///< set when the user asks for a PNG of the view
};

/// Builds this frame's ImGui content (between ImGui::NewFrame and Render).
void build_ui(Editor& editor, const UiInfo& info);

}  // namespace cmr::edit
