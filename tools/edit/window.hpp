#pragma once
// `cmr edit`: the desktop window (GLFW, Vulkan presentation, Dear ImGui), its
// frame loop, scripted runs and the benchmark.
#include <filesystem>
#include <optional>
#include <string>

#include "spline/space.hpp"
#include "tools/edit/region_painter.hpp"

namespace cmr::edit {

struct EditOptions {
  std::filesystem::path file;        ///< spline, font (with glyph) or SVG to open; empty: a cubic Bezier to start from
                                     ///< (a spline file with [x, y, z] points opens in the orbit view, orbit.hpp)
  std::string glyph;                 ///< a font's glyph (every contour opened; sources.hpp)
  std::filesystem::path script;      ///< empty: interactive
  std::filesystem::path screenshot;  ///< PNG of the presented image after the script (or the first frames)
  int width = 1024, height = 768;    ///< window size in pixels
  std::string device;                ///< Vulkan device name (substring)
  bool vsync = true;
  RegionPath region_path = RegionPath::automatic;  ///< how the region reaches the window
  std::optional<vk::RegionPrecision> precision;     ///< the gpu path's shader arithmetic
  /// The point selected when the editor opens; nothing: the first point whose
  /// region shows (Editor::open_on_region_point).
  std::optional<int> point;
  /// A space curve opened from elsewhere than `file` (`cmr edit MODEL.step
  /// --edge '#1234'`: the edge, cmd_space.hpp open_step_edge); `file` is
  /// then where save writes it.
  std::optional<SpaceSpline> space;
  std::string source_label;  ///< what was opened, for the first line (`model.step, edge #1234`)
};

/// Runs the editor until the window closes or the script ends. Returns the
/// exit code. Throws InputError (bad file, script or option: exit 2) and
/// EnvironmentError (spline/errors.hpp: no display, no Vulkan device: exit 3).
/// The exit code of a run that ends normally (the window closed, the script
/// ran, the benchmark finished).
inline constexpr int kEditOk = 0;
int run_editor(const EditOptions& options);

struct BenchOptions {
  std::filesystem::path file;  ///< empty: the Fig. 8 spline (fig8_spline, embedded)
  int width = 1024, height = 768;
  int frames = 200;
  int point = 3;               ///< the dragged point
  /// Locality: region frames of a spline of this many points against a
  /// 6-point one's (0: not measured).
  int points = 10000;
  std::string device;
  RegionPath region_path = RegionPath::automatic;
};

/// Replays a scripted drag in a real window (vsync off), once showing the
/// dragged point's region and once with every point overlapped, and prints
/// frame times (mean, p50, p95, fps) with the CPU model and Vulkan device.
/// A space curve's file: the orbit view's drag of the point in its default
/// plane instead (one run; --region-path is refused).
int run_bench(const BenchOptions& options);

}  // namespace cmr::edit
