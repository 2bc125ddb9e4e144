#pragma once
// `cmr edit SPACE.json`: the orbit view of a space curve (issue 40, item 5).
//
// The model (no window; tests/tools/edit_orbit_test.cpp drives it headless):
//
// Camera. A perspective camera looking at `target` from
//   eye = target + distance (cos p cos y, cos p sin y, sin p)
// (yaw y about the z axis, pitch p above the xy plane; z is up). forward =
// (target - eye) / distance, right = forward x z / |forward x z|, up = right
// x forward. A world point q projects to the canvas pixel
//   s = (cx + f (q - eye).right / depth, cy - f (q - eye).up / depth),
// depth = (q - eye).forward > 0, with f = (H / 2) / tan(fov / 2) and (cx, cy)
// the canvas centre. The pixel s unprojects to the ray eye + t r,
// r = forward + ((sx - cx) / f) right - ((sy - cy) / f) up.
//
// Dragging in a plane. Point K moves in the plane Q(a, b) = O + a U + b V that
// is fixed when the drag starts: by default `cmr region FILE --point K`'s
// plane without --plane (default_space_plane: through P_K spanned by the
// directions to its neighbours), or "screen" (through P_K spanned by the
// camera's right and up), or xy / yz / zx through P_K (parse_space_plane).
// (The screen plane is the one of the view in which the drag starts: taken
// again when a drag starts after the camera turned.)
// The pointer's ray meets the plane where t = ((O - eye).n) / (r.n), n = U x V;
// (a, b) solve the 2 x 2 normal equations [U.U U.V; U.V V.V] (a, b) =
// (U.(X - O), V.(X - O)), and the point is put at exactly O + a U + b V (in
// double), so it stays in the plane to rounding. A ray parallel to the plane
// (|r.n| < 1e-9 |r| |n|) or meeting it behind the eye leaves the point where
// it is.
//
// The region. Point K's certified region in that plane: the labels of
// SpaceRegionProblem (region/space_region.hpp, the CPU path of `cmr region
// SPACE.json --point K --plane ...`) over the plane's default view, drawn in
// the plane. The region of K depends on every point but K, not on where K is
// in the plane: a drag within the fixed plane leaves it as it is, so it is
// computed when the selection, the plane kind or another point changes (a
// fix, an undo): at once at low resolution (kLowRegion pixels a side), then
// at full resolution (kFullRegion) on a thread of its own, shown when it is
// done. The label of K's current position (classify at its plane
// coordinates) is computed every time K moves: the verdict shown live.
//
// Curve, comb, torsion. The curve is sampled (kSamples per segment); the comb
// of a sample C(t) is the tooth C + s kappa N, N = ((C' x C'') x C') / |...|
// the principal normal (towards the centre of curvature), as the space
// report's projections draw it, s = comb_size * 0.2 * (bounding-box diagonal)
// / max kappa. The curve is coloured by its torsion tau = det(C', C'', C''')
// / |C' x C''|^2 (space_torsion): green where tau > 0, purple where tau < 0,
// the hue's strength |tau| / max |tau| from dark grey (tau = 0).
#include <algorithm>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bezierize/space_analyze.hpp"
#include "region/space_region.hpp"
#include "spline/space.hpp"
#include "tools/edit/editor.hpp"

namespace cmr::edit {

/// The side panel's width in pixels.
inline constexpr int kOrbitPanel = 300;

struct OrbitCamera {
  double yaw = 0.7, pitch = 0.5;  ///< radians
  double distance = 10;
  Vec3 target{0.0};
  double fov = 0.7;  ///< vertical field of view, radians
};

/// The camera's frame for a canvas (see the header comment).
struct OrbitProjection {
  Vec3 eye{0.0}, forward{0.0}, right{0.0}, up{0.0};
  double focal = 1, cx = 0, cy = 0;
  /// false when q is not in front of the eye.
  bool to_screen(const Vec3& q, Vec2& s) const;
  Vec3 ray(Vec2 s) const;
};
OrbitProjection orbit_projection(const OrbitCamera& camera, int width, int height);

enum class OrbitPlane { region, screen, xy, yz, zx };
/// "region", "screen", "xy", "yz", "zx"; InputError otherwise.
OrbitPlane parse_orbit_plane(const std::string& text);
const char* orbit_plane_name(OrbitPlane p);

/// A computed region of one point in one plane.
struct OrbitRegion {
  int point = -1;
  SpacePlane plane;
  View view;
  int width = 0, height = 0;
  std::vector<Direction> labels;  ///< row 0 at the top of the view (b = y1)
  bool full = false;              ///< the full resolution
  double seconds = 0;
  /// With the full resolution, when the monotone pixels' box (a whole number
  /// of cells, 2 cells of margin) covers under a quarter of the view's area:
  /// the region again over that box at the full resolution, so a small region
  /// is not drawn in a few coarse cells (empty otherwise). Cells of `labels`
  /// inside `detail_view` are drawn from `detail` instead.
  View detail_view;
  int detail_width = 0, detail_height = 0;
  std::vector<Direction> detail;
};

struct CurveSample {
  double t = 0;
  Vec3 p{0.0}, comb{0.0};  ///< the point and its comb tooth's tip
  double kappa = 0, tau = 0;
};

class OrbitView {
 public:
  static constexpr int kLowRegion = 40, kFullRegion = 160, kSamples = 48;

  OrbitView(SpaceSpline spline, std::filesystem::path path, int width, int height);
  ~OrbitView();
  OrbitView(const OrbitView&) = delete;
  OrbitView& operator=(const OrbitView&) = delete;

  const SpaceSpline& spline() const { return spline_; }
  const std::filesystem::path& path() const { return path_; }
  const SpaceAnalysis& analysis() const { return analysis_; }
  const std::vector<CurveSample>& samples() const { return samples_; }
  double kappa_min() const { return kappa_min_; }
  double kappa_max() const { return kappa_max_; }
  double tau_max() const { return tau_max_; }  ///< max |tau| of the samples
  /// The certified curvature extrema inside the segments (space_curvature_extrema,
  /// as the space report lists them): where, and whether a maximum of |kappa|.
  struct Extremum {
    Vec3 p{0.0};
    double t = 0, kappa = 0;
    bool maximum = false;
  };
  const std::vector<Extremum>& extrema() const { return extrema_; }

  OrbitCamera camera;
  int width() const { return width_; }
  int height() const { return height_; }
  void resize(int w, int h);
  /// The canvas's projection: centred on the window less the panel on its right.
  OrbitProjection projection() const {
    return orbit_projection(camera, std::max(1, width_ - panel_width), height_);
  }
  int panel_width = kOrbitPanel;  ///< pixels the side panel covers (0 with panels off; build_orbit_ui sets it)
  /// The target at the control points' bounding-box centre, the distance so the box fits.
  void fit();
  /// Yaw and pitch in degrees (pitch clamped to +-89).
  void orbit(double yaw_deg, double pitch_deg);
  /// Turns the camera towards the selected point's plane: yaw and pitch of its
  /// normal (the side with z >= 0), the pitch kept within 20..65 degrees so
  /// that z stays up and the curve's height shows; then fit(). (The view
  /// `cmr edit` opens with.)
  void face_plane();
  /// The distance divided by f (> 0): f > 1 comes closer.
  void zoom(double f);
  /// Moves the target by a pointer motion of (dx, dy) pixels at the target's depth.
  void pan(double dx, double dy);

  // Pointer input (window pixels): left on a point drags it in its plane,
  // left elsewhere orbits (0.3 degrees a pixel), right or middle pans; the
  // wheel zooms (1.1 per step).
  void mouse_move(double x, double y);
  void mouse_button(MouseButton button, bool down);
  void scroll(double dy);
  /// The point within 9 pixels of s (the nearest), or -1.
  int pick(Vec2 s) const;
  int dragging() const { return dragging_; }

  int selected() const { return selected_; }
  void select(int k);
  /// Selects `point` (InputError when out of range), or else the first point,
  /// in index order, whose low-resolution region in its default plane has at
  /// least 4 monotone pixels (else the one with the most, else P0; the
  /// search stops after 3 s, for high degrees); the message says which and why.
  void open_on_region_point(std::optional<int> point);
  OrbitPlane plane_kind() const { return plane_kind_; }
  void set_plane_kind(OrbitPlane p);
  /// The plane the selected point moves in (fixed until the selection, the
  /// kind or another point changes); nullopt with the reason in message()
  /// when it is degenerate.
  const std::optional<SpacePlane>& plane() const { return plane_; }
  /// The selected point's plane coordinates (a, b) in plane().
  Vec2 plane_coordinates(const Vec3& q) const;
  Vec3 plane_point(double a, double b) const;
  /// Moves the selected point to the plane's point under pixel s; false
  /// (nothing moves) when the ray misses the plane.
  bool move_to_screen(Vec2 s);
  /// Moves the selected point to plane coordinates (a, b).
  void move_in_plane(double a, double b);
  /// The certified label of the selected point's current position in its plane.
  Direction label_here() const { return label_here_; }

  /// The region to draw (low or full resolution); nullptr without a plane.
  const OrbitRegion* region();
  /// Waits for the full-resolution region.
  void settle();

  bool comb = true;
  double comb_size = 1;
  bool show_region = true;
  bool panels = true;  ///< the legend and side panel (script `ui on|off`)
  std::string message;

  /// `cmr fix`'s search for space curves (design/space_fix.hpp), cmrwi, 5 s; one undo step.
  void fix();
  void undo();
  void redo();
  /// The spline file (space_spline_to_json), written atomically.
  void save(const std::filesystem::path& p);

 private:
  void set_spline(SpaceSpline s, bool others_changed);
  void analyse();
  void reset_plane();
  void update_label();
  void start_full_region();
  SpaceSpline spline_;
  std::filesystem::path path_;
  SpaceAnalysis analysis_;
  std::vector<CurveSample> samples_;
  double kappa_min_ = 0, kappa_max_ = 0, tau_max_ = 0;
  std::vector<Extremum> extrema_;
  int width_ = 0, height_ = 0;
  int selected_ = 0, dragging_ = -1;
  OrbitPlane plane_kind_ = OrbitPlane::region;
  std::optional<SpacePlane> plane_;
  Direction label_here_ = Direction::undecided;
  std::optional<OrbitRegion> region_;
  std::future<OrbitRegion> pending_;
  long pending_generation_ = -1;
  std::vector<std::future<OrbitRegion>> stale_;  ///< superseded renders, dropped when done
  long generation_ = 0;  ///< bumped when the region's inputs change
  std::optional<MouseButton> held_;
  Vec2 last_{0.0};
  std::vector<SpaceSpline> undo_, redo_;
  std::optional<SpaceSpline> drag_start_;
};

/// Keys: f fit, x fix, c comb, ctrl-z undo, ctrl-y redo.
void orbit_key(OrbitView& view, const std::string& name, bool ctrl);

/// The orbit view's ImGui content (canvas overlay, legend, panel).
void build_orbit_ui(OrbitView& view, double frame_ms);
/// The legend's lines: "kind r,g,b words" (the script's `legend`).
std::vector<std::string> orbit_legend(const OrbitView& view);

}  // namespace cmr::edit
