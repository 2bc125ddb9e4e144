#pragma once
// The editor without a window: input handlers (window pixels), named actions
// (what the UI's buttons and the script's commands call), and what the view
// shows (region layers, verdicts, curvature events), recomputed lazily. The
// window (window.cpp) feeds real GLFW input into the same handlers a script
// (script.hpp) feeds its events into.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tools/edit/engine.hpp"
#include "tools/edit/model.hpp"
#include "tools/edit/sources.hpp"
#include "design/fix.hpp"
#include "region/weight_region.hpp"

namespace cmr::edit {

enum class MouseButton { left, right, middle };

/// The pixel factor of the opening search's grid for a canvas: about
/// Editor::kOpeningGrid pixels across its longer side. (A coarser grid for
/// curves with many points missed thin regions, and the cost per point is
/// mostly the region's setup, not the pixels.)
int opening_coarse(std::pair<int, int> canvas);

class Editor {
 public:
  /// Pick radius of a control point, in window pixels.
  static constexpr double kPickRadius = 9;
  /// Zoom factor of one scroll step.
  static constexpr double kZoomStep = 1.25;
  /// Weight factor of one shift+scroll step over a point.
  static constexpr double kWeightStep = 1.1;
  /// The weights the editor allows: any in [-kMaxWeight, kMaxWeight] (a
  /// weight <= 0 may make a pole: analyze reports it, the region is then
  /// empty and the curve is drawn broken there); set_weight clamps and says so.
  static constexpr double kMaxWeight = 1e3;
  /// Window pixels the panels take at the right and the bottom (fit_view
  /// leaves them out while the UI is shown).
  static constexpr int kPanelWidth = 340, kPlotHeight = 190;

  Editor(BSpline spline, std::filesystem::path path, int width, int height);

  // ---- input, in window pixels (row 0 at the top) ----
  void mouse_move(double x, double y);
  /// Left: press on a point starts dragging it (shift: adds it to / removes
  /// it from the rigid group instead); right or middle: pans.
  void mouse_button(MouseButton button, bool down, bool shift);
  /// Zooms about the cursor (dy > 0: closer); with shift over a control
  /// point, scales that point's weight by kWeightStep^dy instead.
  void scroll(double dy, bool shift = false);
  /// Key by name ("z" with ctrl: undo, "y" with ctrl: redo, "c": CMR/CMRWI,
  /// "d": depth shading, "a": all points, "g": chain mode, "f": fit view,
  /// "x": fix, "s": snap the selected point into its region).
  void key(const std::string& name, bool ctrl);

  // ---- actions (UI and script); bad values throw InputError ----
  void select(int k);
  void set_group(std::vector<int> group);
  void set_all_points(bool on);
  void set_mode(Mode mode);
  void set_depth(int depth);
  void set_depth_shading(bool on);
  void set_split(std::optional<int> joint);
  void set_chain(bool on);
  /// Which segments the region and the verdicts judge (RegionRequest::
  /// segments): first..last, or all when empty. InputError for a range the
  /// curve lacks (bezierize/segments.hpp's judged_range); a split joint not
  /// inside the new range is dropped (the status line says so).
  void set_segments(std::optional<SegmentRange> range);
  /// κ-curve mode (model.hpp's KCurveDesign): on starts an empty design (left
  /// clicks on the canvas add interpolation points), off leaves the mode and
  /// keeps the curve. One undo step each, as every point and the switch.
  void set_kcurve(bool on);
  void set_kcurve_closed(bool closed);
  /// Adds an interpolation point (world); the curve is the κ-curve through
  /// the points once there are kKCurveMinPoints. A point the κ-curve refuses
  /// (too close to the previous one) is not added: the status line says why.
  void add_kcurve_point(Vec2 p);
  /// Switches to modification: the spline becomes the κ-curve's cubic chain
  /// in chain mode, the handle after the first interior maximum selected.
  void kcurve_modify();
  /// Point k to world position p as a drag would put it (group, chain rules).
  void move_point(int k, Vec2 p);
  /// The weight of point k (a polynomial spline becomes rational, its other
  /// weights 1; weights all 1 again make it polynomial): with_weight of
  /// region/weight_region.hpp. A weight outside [-kMaxWeight, kMaxWeight] is
  /// clamped and the status line says so; InputError for a point out of
  /// range, a weight that is not a number, every weight 0, and in κ-curve mode (the curve
  /// is rebuilt from its points there). Consecutive changes of one point's
  /// weight (a drag of the field) are one undo step.
  void set_weight(int k, double w);
  /// Knot i to value u (polar index; knot_ops' set_knot, whose InputError
  /// says why a value is refused). Consecutive moves of one knot (a ruler
  /// drag) are one undo step.
  void move_knot(int i, double u);
  /// A knot operation by name (engine.hpp's knot_operation); one undo step.
  /// A refused operation (InputError: e.g. a removal beyond the tolerance)
  /// changes nothing, puts "refused: <why>" in the status line and returns
  /// false.
  bool knot_operation(const std::string& name, double a, double b);
  /// Replaces the spline (knot operations); one undo step (merged with the
  /// previous one when both have the same non-empty merge_key).
  void replace_spline(BSpline spline, const std::string& what, const std::string& merge_key = {});
  bool undo();
  bool redo();
  void save(const std::filesystem::path& path);
  /// The region of the current state for the whole window's view and size,
  /// as `cmr region --view ... --size WxH` computes it: PATH ending in .png,
  /// the picture of `--png`; otherwise the labels of `--labels` (one PGM;
  /// with every point overlapped, PATH.P0.pgm, PATH.P1.pgm, ...).
  void export_region(const std::filesystem::path& path);
  void resize(int width, int height);
  void set_view(View view);
  /// Frames the control polygon, the curvature comb (as drawn at scale 1 in
  /// the polygon's view) and the selected point's region (within twice that
  /// view): what the first view and "fit" show (tools/edit/designer.cpp).
  void fit_view();
  /// "fit region": frames the selected point's region (its box on a grid of
  /// 128 pixels over a view 4 times the canvas's) and the point; the status
  /// line says so, or that the region is empty there.
  void fit_region();
  /// Frames the world box lo..hi in the canvas with `margin` of its size around.
  void frame_box(Vec2 lo, Vec2 hi, double margin);

  // ---- designer's read-outs (tools/edit/designer.cpp) ----
  /// The file's point names (read_point_names), one per distinct point.
  std::vector<std::string> point_names;
  /// Point k's name: the file's point_names (a closed curve's repeated
  /// points take their first's), else "P<k>".
  std::string point_name(int k) const;
  /// Every point overlapped: the points whose regions are not drawn.
  std::vector<int> hidden_points;
  void set_point_shown(int k, bool shown);
  /// The point each region layer belongs to (region_requests' order).
  std::vector<int> layer_points() const;
  // ---- several curves: a glyph's contours, an SVG's paths (tools/edit/sources.cpp) ----
  /// The curves opened together (empty or one: a single spline file); the
  /// document holds the active one's spline, the others are drawn beside it.
  std::vector<OpenedCurve> curves;
  int active_curve = 0;
  std::filesystem::path font_path;  ///< a font: the glyph picker's source
  /// Takes the curves of an opened source, the first one active.
  void set_source(OpenedSource source);
  /// Edits curve k instead (the active one keeps its edits); undo starts
  /// again there. InputError for a curve the source lacks.
  void switch_curve(int k);
  /// The glyph picker: every contour of glyph `spec` of font_path.
  void open_glyph(const std::string& spec);
  /// Writes every curve (the active one as edited) to its spline JSON
  /// (OpenedCurve::save_as, with its point names); the status line says where.
  void save_all();
  /// A press on another curve's point makes that curve active and selects it.
  bool pick_other_curve(double x, double y);
  // ---- a font source's glyph (a UFO's or a .glif's; tools/edit/sources.cpp) ----
  /// The .glif the glyph was read from (empty: not a font source); "save"
  /// and "save all" write back into it (save_source).
  std::filesystem::path source_glif;
  /// The font's grid (font units; 0: none): a dragged point lands on it and
  /// save_source rounds to it.
  double grid = 0;
  /// Whether control point k of the edited curve is one a designer moves: not
  /// a straight piece's added inner point of a font source (those are
  /// neither drawn nor picked, and follow their line's end nodes).
  bool movable(int k) const;
  /// Point k's name as the canvas labels it: for a font source's contour the
  /// part after "GLYPH/cC/" ("p3", "n3.out"), else point_name(k).
  std::string short_point_name(int k) const;
  /// What the pointer over window pixel (x, y) shows of a point (the edited
  /// curve's, else another opened curve's): its full name and coordinates,
  /// "O/c0/p3 (700, 300)"; empty when no point is within kPickRadius.
  std::string point_hover(double x, double y) const;
  /// After a move of a font source's contour: every straight piece whose end
  /// node moved gets its inner points back on the line (as the importer
  /// places them), so a line stays a line.
  BSpline keep_lines(const BSpline& before, BSpline after) const;
  /// Writes every contour's moved source points back into source_glif, as
  /// `cmr fix --in-place` does (io/ufo.hpp's rewrite_glif_points, staged
  /// through the OutputSet): only the moved points' x and y attributes
  /// change, rounded to the grid; every other byte stays. InputError when a
  /// contour's knots or point count changed (a knot operation) or it became
  /// rational: a .glif holds point positions only.
  void save_source();
  /// The curvature comb of every opened curve, not only the edited one.
  bool comb_all_curves = false;
  /// Constrained drag (issue 21, item 6): a dragged point that stands in its
  /// region stays in it: where the pointer leaves the region the point stops
  /// at the last position on the way there that RegionProblem::classify
  /// certifies inside (bisection to kConstrainSteps halvings). A point
  /// outside its region moves freely until it enters. The selected point
  /// alone (not with every point overlapped or in kappa-curve mode).
  bool constrain_drag = false;
  static constexpr int kConstrainSteps = 40;
  /// Where a constrained drag of the selected point from `from` towards `to`
  /// ends (to itself when unconstrained or when `to` is inside).
  Vec2 constrained_target(Vec2 from, Vec2 to) const;
  /// Whether position p is certified inside the selected point's region
  /// (its current request: mode, split, segments, group, chain).
  bool in_selected_region(Vec2 p) const;
  /// Typed coordinates: point k to exactly (x, y) (its group and chain rules
  /// as a drag); one undo step.
  void set_point_xy(int k, double x, double y);

  // ---- opening and repair (tools/edit/repair.cpp) ----
  /// The opening selection (docs/edit.md): the first point, in index order,
  /// whose region (the current mode, split, judged segments; a closed curve's
  /// default: the spans the point acts on) has at least kOpeningCells
  /// certified monotone pixels on a grid of about kOpeningGrid pixels across
  /// the canvas's view (opening_coarse; the CPU engine, RegionProblem's
  /// labels); when none has that many, the point with the most (the first of
  /// equals), if any. When none has one, P0 stays selected and the status line says so
  /// with the first reason (region/region_reason.hpp) that names the
  /// segments responsible (P0's unless its support wraps a closed curve's
  /// seam). Not an undo step. Returns the point chosen,
  /// or nothing. With `named` (`cmr edit --point K`) that point is opened
  /// instead (InputError when the curve has no point K).
  std::optional<int> open_on_region_point(std::optional<int> named = std::nullopt);
  static constexpr int kOpeningGrid = 64, kOpeningCells = 4;
  /// A closed curve judged over every segment (no split, not each-piece):
  /// the region of one point judges the spans it acts on, as `cmr region`
  /// does; this is that range for the selected point (nothing otherwise).
  std::optional<SegmentRange> closed_support() const;
  /// The requirement the view implies (what `fix` and `snap` reach): split:S
  /// with a split joint, each-piece in Bezier-chain mode, else the mode
  /// (cmrwi or cmr), over every segment (as `cmr fix --require`).
  FixRequirement fix_requirement() const;
  /// "fix": bezierize/fix's nearest certified fix of fix_requirement(), the
  /// points it chooses moving (cmr fix's default request: G1 kept at G1
  /// joints, the end points of an open curve fixed), at most kFixSeconds of
  /// search. The move is animated over kFixAnimationSeconds of frames
  /// (advance_animation) and is one undo step. No fix: nothing moves, the
  /// status line says why in one line and the result is false.
  bool fix_curve();
  /// A glyph's contour (curves with font points): the points a chain-mode
  /// fix may move: the font's own points (not a line's added ones) that act
  /// on a segment whose curvature is not certified monotone, except a node
  /// at an end of a straight piece (it stays, so the line stays the same
  /// line). Empty for other curves (every point may move).
  std::vector<int> glyph_fix_points() const;
  /// "fix on the grid" (a font's glyph): the edited contour fixed as `cmr
  /// fix FONT.ufo --glyph NAME --require GATES` fixes it, GATES being
  /// grid_fix_gates (report/glyph_fix.hpp: one fix for all of them, only the
  /// font's own points, lines kept, smooth nodes kept smooth, positions on
  /// the grid, re-judged gate by gate), animated and undoable as fix_curve;
  /// saved, it is written as found. At most kFixSeconds per stage. No fix,
  /// or a gate list report::parse_require_list refuses: the status line
  /// says why and nothing moves.
  bool fix_on_grid();
  static constexpr const char* kGridFixRequirement = "curvature-extrema-at-nodes";
  /// The gates "fix on grid" asks for, comma-separated as in `--require`
  /// (the panel's choice; script `fix-grid GATES`).
  std::string grid_fix_gates = kGridFixRequirement;
  /// "snap into region": the selected point alone (its own region, no rigid
  /// group) to the nearest certified position of fix_requirement() found by
  /// bezierize/fix (FixRequest::points = {selected}; in chain mode G1 kept),
  /// animated and undoable as fix_curve.
  bool snap_selected();
  bool animating() const { return animation_.has_value(); }
  /// Moves an animated fix on by `seconds` (the window calls it every frame).
  void advance_animation(double seconds);
  /// Puts an animated fix at its end at once (a new action interrupts it).
  void finish_animation();
  static constexpr double kFixAnimationSeconds = 0.4;
  static constexpr double kFixSeconds = 5;

  // ---- what is shown ----
  const Document& doc() const { return history_.current(); }
  const Viewport& viewport() const { return viewport_; }
  const std::filesystem::path& path() const { return path_; }
  int dragging() const { return dragging_; }
  /// The part of the window the region is computed for: all of it without
  /// the UI, else the top-left rectangle the opaque panels leave free (the
  /// pixels under them are never seen).
  std::pair<int, int> canvas() const;
  /// The requests the region view answers now, one per layer (every point
  /// alone when all are overlapped, else the selected point with its rigid
  /// group and, in chain mode, an anchor's handles as `with`): the canvas's
  /// pixels, with the same pixel size and top-left corner as the window's
  /// view (the whole window's view exactly when the canvas is the whole
  /// window, or with whole_window). With coarse = c > 1 the pixels are c
  /// times larger each way (ceil(canvas / c) of them, the same top-left
  /// corner): each coarse pixel's label is the certified label of its centre.
  std::vector<RegionRequest> region_requests(bool whole_window = false, int coarse = 1) const;
  /// The spline the region requests are for: the document's, or, modifying a
  /// κ-curve, the cubic piece the selected handle shapes (as a Bezier curve;
  /// the requests then name the handle's index in it; none for an anchor).
  BSpline region_spline() const;
  /// Pixel size factor of the region while a point is dragged or the view
  /// panned: a quarter of the pixels keeps dragging above 30 frames per
  /// second on a 2-core lavapipe machine (README, `cmr edit --bench`). When
  /// the drag ends the full-resolution region replaces it.
  static constexpr int kDragCoarse = 2;
  /// The factor of the region shown now (1, or kDragCoarse while dragging).
  int region_coarse() const { return region_coarse_; }
  /// Region layers for the current state (recomputed when stale, from the
  /// cache when only the moved group changed); `changed` is set when they
  /// differ from the last call's. While a point is dragged or the view
  /// panned, layers the cache lacks are computed kDragCoarse times coarser.
  const std::vector<const RegionResult*>& region(bool* changed = nullptr);
  /// Counts the changes of region()'s layers (what is derived from them is
  /// cached by it: the legend, the outlines).
  long region_serial() const { return region_serial_; }
  /// RGBA of the whole window: region() in the legend's colours on the
  /// canvas, white elsewhere.
  const std::vector<uint8_t>& region_rgba(bool* changed = nullptr);
  const SplineAnalysis& analysis();
  const CurvatureEvents& events();
  /// The per-span setup remembered between moves (region/region_memo.hpp):
  /// every region problem and verdict the editor makes goes through it.
  RegionMemo& memo() const { return *memo_; }
  /// The region of the selected point's weight (region/weight_region.hpp,
  /// `cmr region --weight K`) over [w/4, 4w] of its weight w (ends in
  /// increasing order for w < 0; [-1, 1] for w = 0), in the view's labels (mode, split, segments,
  /// depth), kWeightRegionSamples samples: nullptr unless
  /// show_weight_region, or in κ-curve mode. Recomputed when the document
  /// changed, except while a point is dragged (the last one is kept);
  /// `request`, when given, receives the request it answers.
  const WeightRegion* weight_region_view(WeightRegionRequest* request = nullptr);
  static constexpr int kWeightRegionSamples = 65;
  bool show_weight_region = false;
  /// Status line: the last action's result or error.
  std::string message;
  bool show_ui = true;       ///< the panels
  bool show_overlay = true;  ///< curve, polygon, points, comb
  bool show_comb = true;
  bool show_legend = true;   ///< the legend at the canvas's top left (designer.hpp's region_legend)
  /// The legend as a section of the side panel instead of over the canvas's
  /// top left, where it never covers the curve (the default for a font
  /// source's glyph, whose contours fill the view).
  bool legend_docked = false;
  /// Comb length relative to the fitted comb (designer.hpp's comb_geometry:
  /// 1 fits the canvas's view).
  double comb_scale = 1.0;
  int comb_density = 24;     ///< comb teeth per segment
  bool comb_outline = true;  ///< the line joining the teeth's tips
  /// The curvature graph: 0 kappa, 1 |kappa|, 2 log10 |kappa|.
  int graph_view = 0;

 private:
  /// region_requests for a document (the opening search tries each point).
  std::vector<RegionRequest> requests_of(const Document& d, bool whole_window, int coarse) const;
  bool apply_fix(const FixRequest& request, const std::string& what);
  struct Animation {
    BSpline from, to;
    double t = 0;  ///< 0..1
    std::string key;
    long changes = -1;  ///< History::changes() after its last frame
    bool first = true;  ///< the next frame's time includes the search: one frame's step at most
  };
  std::optional<Animation> animation_;
  int fix_serial_ = 0;
  int pick(double x, double y) const;
  void changed_document();
  History history_;
  std::filesystem::path path_;
  Viewport viewport_;
  Vec2 mouse_{0.0};
  int dragging_ = -1;
  Vec2 grab_offset_{0.0};  ///< point - cursor (world) at the press
  bool panning_ = false;
  int drag_serial_ = 0;
  bool region_stale_ = true, rgba_stale_ = true, analysis_stale_ = true, events_stale_ = true;
  RegionCache cache_;
  std::vector<uint8_t> region_part_;  ///< the region's colours before scaling to the window (reused)
  std::shared_ptr<RegionMemo> memo_ = std::make_shared<RegionMemo>();
  std::vector<const RegionResult*> region_;
  std::vector<std::vector<double>> region_keys_;
  std::pair<int, int> region_canvas_{0, 0};
  int region_coarse_ = 1;
  long region_serial_ = 0;
  std::vector<uint8_t> rgba_;
  std::optional<SplineAnalysis> analysis_;
  bool weight_region_stale_ = true;
  std::optional<WeightRegion> weight_region_;
  WeightRegionRequest weight_request_;
  CurvatureEvents events_;
};

}  // namespace cmr::edit
