#pragma once
// The editor's state without any window: the spline being designed, what the
// region view shows, the world view, and undo/redo. Every change a user makes
// (mouse, keys, UI, script) goes through these functions, so the window code
// and the tests drive the same logic.
#include <optional>
#include <string>
#include <vector>

#include "bezierize/analyze.hpp"
#include "region/region.hpp"
#include "bezierize/segments.hpp"
#include "spline/bspline.hpp"
#include "spline/limits.hpp"

namespace cmr::edit {

/// κ-curve design (CAD&A 2024 §5.2, Application 2): first the interpolation
/// points are clicked and the κ-curve through them is shown (as quadratics);
/// then, modifying, the curve is its cubic chain (each quadratic split at its
/// curvature maximum and degree-elevated) in chain mode, and the region shown
/// is the selected handle's within the one cubic piece it shapes: where the
/// handle may go without a new curvature extremum in that piece (Fig. 13).
struct KCurveDesign {
  std::vector<Vec2> points;  ///< interpolation points, in click order
  bool closed = false;
  bool modifying = false;    ///< the cubic chain is being modified
};

/// What is designed and how it is judged: the part of the state undo restores.
struct Document {
  BSpline spline;
  int selected = 0;            ///< the point whose region is shown (and dragged last)
  std::vector<int> group;      ///< rigid companions of `selected` (move with it by the same vector)
  bool all_points = false;     ///< overlap the regions of every point (Fig. 3)
  Mode mode = Mode::cmrwi;
  int max_depth = kDefaultDepth;
  bool depth_shading = false;  ///< Fig. 7
  std::optional<int> split;    ///< extremum at joint S
  bool chain = false;          ///< Bezier-chain mode: G1 handles follow their anchor
  std::optional<KCurveDesign> kcurve;  ///< κ-curve mode
  std::optional<SegmentRange> segments;  ///< only these segments are judged (RegionRequest::segments)
};

/// In a cubic Bezier chain (chain_anchors), the piece point k shapes as a
/// Bezier curve of its own and k's index in it: {piece, local}; nullopt for
/// an anchor or end point (shared by two pieces, or not a handle) or a spline
/// that is not a cubic chain.
struct HandlePiece {
  BSpline piece;
  int local = 0;
};
std::optional<HandlePiece> handle_piece(const BSpline& chain, int k);

/// In a Bezier chain (every interior knot of multiplicity d, so the joints are
/// control points), the anchor point of each interior joint, in order.
std::vector<int> chain_anchors(const BSpline& spline);

/// Moves point k (and its rigid group, by the same vector) so that k lands on
/// p. In chain mode, an anchor carries its two handles along, and a handle
/// next to an anchor turns the opposite handle so the three stay collinear
/// (the opposite handle keeps its length): G1 at the joint (CAD&A 2024,
/// Application 1). Throws InputError for a non-finite p.
BSpline move_point(const Document& doc, int k, Vec2 p);

/// Points that move with k when it is dragged by translation (k first): its
/// rigid group when k is the selected point, and, in chain mode, an anchor's
/// two handles.
std::vector<int> translation_group(const Document& doc, int k);

/// World rectangle of the window (x0 left, x1 right, y0 bottom, y1 top) and
/// the conversions between window pixels and world points. Pixel centres are
/// exactly those of cmr::pixel_center, so the region shown is `cmr region
/// --view x0,y0,x1,y1 --size WxH`.
struct Viewport {
  View view;
  int width = 1, height = 1;
  Vec2 to_world(double px, double py) const;
  Vec2 to_screen(Vec2 w) const;
  /// Fits the spline's control polygon into the top-left `canvas_w` x
  /// `canvas_h` pixels of the window (cmr::default_view for that size, the
  /// same pixel size beyond it): the rest is under the panels.
  static Viewport fit(const BSpline& spline, int width, int height, int canvas_w, int canvas_h);
  /// Same top-left corner and pixel size, new window size.
  [[nodiscard]] Viewport resized(int w, int h) const;
  /// Shifted by (dx, dy) window pixels (the content follows the mouse).
  [[nodiscard]] Viewport panned(double dx, double dy) const;
  /// Zoomed by `factor` (> 1: closer) keeping the world point under window
  /// pixel (px, py) in place.
  [[nodiscard]] Viewport zoomed(double factor, double px, double py) const;
};

/// Undo and redo over whole documents (splines are small).
class History {
 public:
  explicit History(Document initial) : current_(std::move(initial)) {}
  const Document& current() const { return current_; }
  /// Replaces the current document, remembering the old one for undo; clears
  /// redo. Consecutive commits with the same non-empty `merge_key` (one drag)
  /// make one undo step.
  void commit(Document next, const std::string& merge_key = {});
  /// Ends a merge run (a drag finished): the next commit is a new step.
  void seal() { merge_key_.clear(); }
  bool undo();
  bool redo();
  bool can_undo() const { return !undo_.empty(); }
  /// Counts every commit, undo and redo (an animated fix notices that
  /// another change came between its frames).
  long changes() const { return changes_; }
  bool can_redo() const { return !redo_.empty(); }

 private:
  Document current_;
  std::vector<Document> undo_, redo_;
  std::string merge_key_;
  long changes_ = 0;
};

}  // namespace cmr::edit
