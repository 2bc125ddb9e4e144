#include "tools/edit/editor.hpp"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <cstdio>

#include "bezierize/analyze.hpp"
#include "region/region_reason.hpp"
#include "design/kcurve.hpp"
#include "bezierize/knot_ops.hpp"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"
#include "spline/spline_json.hpp"
#include "io/output.hpp"
#include "draw/draw.hpp"
#include "draw/region_export.hpp"
#include "tools/field_flags.hpp"

namespace cmr::edit {

Editor::Editor(BSpline spline, std::filesystem::path path, int width, int height)
    : history_(Document{std::move(spline), 0, {}, false, Mode::cmrwi, kDefaultDepth, false, std::nullopt, false, std::nullopt, std::nullopt}),
      path_(std::move(path)),
      viewport_(Viewport::fit(history_.current().spline, width, height, width - kPanelWidth, height - kPlotHeight)) {}

void Editor::changed_document() {
  // The colours follow the layers alone: region() marks them stale when the
  // layers' keys change.
  region_stale_ = analysis_stale_ = events_stale_ = weight_region_stale_ = true;
}

int Editor::pick(double x, double y) const {
  int best = -1;
  double best_d = kPickRadius;
  const std::vector<Vec2>& pts = doc().spline.points();
  for (int i = 0; i < static_cast<int>(pts.size()); ++i) {
    if (!movable(i)) continue;  // a font source's line point: not the designer's
    const Vec2 s = viewport_.to_screen(pts[i]);
    const double d = std::hypot(s.x - x, s.y - y);
    if (d <= best_d) best = i, best_d = d;
  }
  return best;
}

void Editor::mouse_move(double x, double y) {
  const Vec2 before = mouse_;
  mouse_ = {x, y};
  if (panning_) {
    viewport_ = viewport_.panned(x - before.x, y - before.y);
    region_stale_ = rgba_stale_ = true;
  }
  if (dragging_ >= 0) {
    Document next = doc();
    Vec2 to = viewport_.to_world(x, y) + grab_offset_;
    if (grid > 0) to = {std::round(to.x / grid) * grid, std::round(to.y / grid) * grid};  // the font's grid
    if (constrain_drag && dragging_ == doc().selected) to = constrained_target(doc().spline.points()[dragging_], to);
    next.spline = keep_lines(doc().spline, edit::move_point(doc(), dragging_, to));
    history_.commit(std::move(next), "drag" + std::to_string(drag_serial_));
    changed_document();
  }
}

void Editor::mouse_button(MouseButton button, bool down, bool shift) {
  if (button != MouseButton::left) {
    if (panning_ && !down) region_stale_ = true;  // full resolution again
    panning_ = down;
    return;
  }
  if (down) finish_animation();
  if (!down) {
    if (dragging_ >= 0) {
      history_.seal();
      region_stale_ = true;  // full resolution again
    }
    dragging_ = -1;
    return;
  }
  if (doc().kcurve && !doc().kcurve->modifying) {  // clicking interpolation points
    add_kcurve_point(viewport_.to_world(mouse_.x, mouse_.y));
    return;
  }
  const int k = pick(mouse_.x, mouse_.y);
  if (k < 0) {
    pick_other_curve(mouse_.x, mouse_.y);  // another contour's point: edit that contour
    return;
  }
  if (shift) {
    std::vector<int> g = doc().group;
    const auto it = std::find(g.begin(), g.end(), k);
    if (it != g.end()) g.erase(it);
    else if (k != doc().selected) g.push_back(k);
    set_group(std::move(g));
    return;
  }
  ++drag_serial_;
  if (k != doc().selected) {  // picking the point is part of the drag's undo step
    Document next = doc();
    next.selected = k;
    std::erase(next.group, k);
    history_.commit(std::move(next), "drag" + std::to_string(drag_serial_));
    changed_document();
  }
  dragging_ = k;
  grab_offset_ = doc().spline.points()[k] - viewport_.to_world(mouse_.x, mouse_.y);
}

void Editor::scroll(double dy, bool shift) {
  if (shift) {
    const int k = pick(mouse_.x, mouse_.y);
    if (k >= 0) {
      set_weight(k, doc().spline.weight(k) * std::pow(kWeightStep, dy));
      return;
    }
  }
  viewport_ = viewport_.zoomed(std::pow(kZoomStep, dy), mouse_.x, mouse_.y);
  region_stale_ = rgba_stale_ = true;
}

void Editor::key(const std::string& name, bool ctrl) {
  if (ctrl && name == "z") undo();
  else if (ctrl && name == "y") redo();
  else if (name == "c") set_mode(doc().mode == Mode::cmr ? Mode::cmrwi : Mode::cmr);
  else if (name == "d") set_depth_shading(!doc().depth_shading);
  else if (name == "a") set_all_points(!doc().all_points);
  else if (name == "g") set_chain(!doc().chain);
  else if (name == "f") fit_view();
  else if (!ctrl && name == "x") fix_curve();
  else if (!ctrl && name == "s") snap_selected();
}

namespace {

void check_point(const BSpline& s, int k) {
  if (k < 0 || k >= s.point_count())
    throw InputError("point " + std::to_string(k) + " is outside 0.." + std::to_string(s.point_count() - 1));
}

}  // namespace

void Editor::select(int k) {
  check_point(doc().spline, k);
  Document next = doc();
  next.selected = k;
  std::erase(next.group, k);
  history_.commit(std::move(next));
  changed_document();
}

void Editor::set_group(std::vector<int> group) {
  for (int k : group) check_point(doc().spline, k);
  Document next = doc();
  std::erase(group, next.selected);
  std::sort(group.begin(), group.end());
  group.erase(std::unique(group.begin(), group.end()), group.end());
  next.group = std::move(group);
  history_.commit(std::move(next));
  changed_document();
}

void Editor::set_all_points(bool on) {
  Document next = doc();
  next.all_points = on;
  history_.commit(std::move(next));
  changed_document();
}

void Editor::set_mode(Mode mode) {
  Document next = doc();
  next.mode = mode;
  history_.commit(std::move(next));
  changed_document();
}

void Editor::set_depth(int depth) {
  if (depth < 0 || depth > kMaxDepth)
    throw InputError("depth " + std::to_string(depth) + " is outside 0.." + std::to_string(kMaxDepth));
  Document next = doc();
  next.max_depth = depth;
  history_.commit(std::move(next), "depth");
  changed_document();
}

void Editor::set_depth_shading(bool on) {
  Document next = doc();
  next.depth_shading = on;
  history_.commit(std::move(next));
  changed_document();
}

void Editor::set_split(std::optional<int> joint) {
  const int n = doc().spline.segment_count();
  if (joint) validate_cuts({*joint}, judged_range(doc().segments, n), n);
  Document next = doc();
  next.split = joint;
  history_.commit(std::move(next));
  changed_document();
}

void Editor::set_segments(std::optional<SegmentRange> range) {
  const int n = doc().spline.segment_count();
  const SegmentRange r = judged_range(range, n);
  Document next = doc();
  next.segments = range;
  message = range ? "judging segments " + std::to_string(r.first) + ".." + std::to_string(r.last) : "judging every segment";
  if (next.split && (*next.split < r.first + 1 || *next.split > r.last)) {
    next.split.reset();
    message += " (split joint dropped: not inside the range)";
  }
  history_.commit(std::move(next));
  changed_document();
}

void Editor::set_chain(bool on) {
  Document next = doc();
  next.chain = on;
  history_.commit(std::move(next));
  changed_document();
}

void Editor::set_kcurve(bool on) {
  Document next = doc();
  if (on) {
    next.kcurve = KCurveDesign{};
    next.all_points = false;
    message = "kappa-curve: click the interpolation points";
  } else {
    next.kcurve.reset();
    message = "kappa-curve mode off";
  }
  history_.commit(std::move(next));
  changed_document();
}

namespace {

KCurve kcurve_of(const KCurveDesign& k) { return kcurve(k.points, {.closed = k.closed}); }

/// The document's spline for a κ design: the quadratics while points are
/// clicked (once there are enough), the cubic chain when modifying.
void rebuild_kcurve(Document& d) {
  const KCurveDesign& k = *d.kcurve;
  if (static_cast<int>(k.points.size()) < kKCurveMinPoints) return;
  const KCurve kc = kcurve_of(k);
  d.spline = k.modifying ? kcurve_cubic_chain(kc) : kcurve_quadratic_spline(kc);
  d.selected = std::min(d.selected, d.spline.point_count() - 1);
  d.group.clear();
  d.split.reset();
  d.segments.reset();
}

}  // namespace

void Editor::set_kcurve_closed(bool closed) {
  if (!doc().kcurve) throw InputError("closed: not in kappa-curve mode (kcurve points)");
  if (doc().kcurve->modifying) throw InputError("closed: the curve is being modified; start again with kcurve points");
  Document next = doc();
  next.kcurve->closed = closed;
  rebuild_kcurve(next);
  history_.commit(std::move(next));
  changed_document();
}

void Editor::add_kcurve_point(Vec2 p) {
  if (!doc().kcurve || doc().kcurve->modifying) throw InputError("kappa-curve points are added in kcurve points mode");
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw InputError("kappa-curve point: not finite");
  Document next = doc();
  next.kcurve->points.push_back(p);
  try {
    rebuild_kcurve(next);
  } catch (const InputError& e) {
    message = std::string("point not added: ") + cli::shown_message(e);
    return;
  }
  history_.commit(std::move(next));
  message = "kappa-curve: " + std::to_string(doc().kcurve->points.size()) + " points";
  changed_document();
}

void Editor::kcurve_modify() {
  if (!doc().kcurve) throw InputError("modify: not in kappa-curve mode (kcurve points)");
  const int n = static_cast<int>(doc().kcurve->points.size());
  if (n < kKCurveMinPoints)
    throw InputError("modify: a kappa-curve needs " + std::to_string(kKCurveMinPoints) + " points, there are " +
                     std::to_string(n));
  Document next = doc();
  next.kcurve->modifying = true;
  next.chain = true;
  next.all_points = false;
  rebuild_kcurve(next);
  next.selected = 1;
  for (int k : kcurve_cubic_maxima(kcurve_of(*next.kcurve)))
    if (k > 0) {  // the handle after the first maximum with a handle pair
      next.selected = k + 1;
      break;
    }
  history_.commit(std::move(next));
  message = "kappa-curve: modify the handles (pairs stay collinear)";
  changed_document();
}

void Editor::move_point(int k, Vec2 p) {
  check_point(doc().spline, k);
  Document next = doc();
  next.spline = keep_lines(doc().spline, edit::move_point(doc(), k, p));
  history_.commit(std::move(next));
  changed_document();
}

void Editor::set_weight(int k, double w) {
  check_point(doc().spline, k);
  if (doc().kcurve) throw InputError("weight: not in kappa-curve mode (the curve is rebuilt from its points)");
  if (std::isnan(w)) throw InputError("weight: not a number");
  const double clamped = std::clamp(w, -kMaxWeight, kMaxWeight);
  BSpline next = with_weight(doc().spline, k, clamped);
  const bool pole = has_pole(next);
  char what[200];
  std::snprintf(what, sizeof what, "weight of P%d set to %.6g%s%s", k, clamped,
                clamped != w ? " (clamped to -1000..1000)" : "",
                pole ? "; the curve has a pole (W = 0): no region" : "");
  replace_spline(std::move(next), what, "weight" + std::to_string(k));
}

void Editor::move_knot(int i, double u) {
  replace_spline(set_knot(doc().spline, i, u), "knot " + std::to_string(i) + " moved", "knot" + std::to_string(i));
}

bool Editor::knot_operation(const std::string& name, double a, double b) {
  try {
    KnotResult r = edit::knot_operation(doc().spline, name, a, b);
    replace_spline(std::move(r.spline), r.message);
    return true;
  } catch (const InputError& e) {
    message = std::string("refused: ") + cli::shown_message(e);
    return false;
  }
}

void Editor::replace_spline(BSpline spline, const std::string& what, const std::string& merge_key) {
  Document next = doc();
  const bool same_points = spline.point_count() == next.spline.point_count();
  next.spline = std::move(spline);
  if (!same_points) {  // indices no longer mean the same points
    next.selected = std::min(next.selected, next.spline.point_count() - 1);
    next.group.clear();
  }
  if (next.segments && next.segments->last > next.spline.segment_count() - 1) next.segments.reset();
  if (next.split && *next.split > next.spline.segment_count() - 1) next.split.reset();
  history_.commit(std::move(next), merge_key);
  message = what;
  changed_document();
}

bool Editor::undo() {
  finish_animation();
  const bool done = history_.undo();
  if (done) changed_document();
  return done;
}

bool Editor::redo() {
  finish_animation();
  const bool done = history_.redo();
  if (done) changed_document();
  return done;
}

void Editor::save(const std::filesystem::path& path) {
  if (!source_glif.empty() && path == source_glif) {  // a font source's glyph: back into its .glif
    save_source();
    return;
  }
  write_curve_file(path, doc().spline, point_names);
  path_ = path;
  message = "saved " + path.string() + " (spline JSON)";
}

void Editor::export_region(const std::filesystem::path& path) {
  const std::vector<RegionRequest> q = region_requests(true);
  if (q.empty()) throw InputError("export-region: no region is shown (select a handle)");
  const BSpline spline = region_spline();
  const std::vector<RegionResult> layers = compute_regions(spline, q, &memo());
  OutputSet out;  // the files of cmr region --png / --labels (draw/region_export.hpp)
  if (path.extension() == ".png") {
    draw::RegionPicture picture = draw::layers_picture(spline, layers, q);
    if (layers.size() == 1)
      picture.note = cli::show_fields(region_reason(memo().make(spline, q.front()), layers[0]).value_or(""));
    out.stage(path, draw::region_png(picture));
  } else {
    draw::stage_label_pgms(out, path, layers, q);
  }
  out.commit();
  message = "region written to " + path.string();
}

void Editor::resize(int width, int height) {
  if (width == viewport_.width && height == viewport_.height) return;
  if (width <= 0 || height <= 0) return;  // minimised: keep the view
  viewport_ = viewport_.resized(width, height);
  region_stale_ = rgba_stale_ = true;
}

void Editor::set_view(View view) {
  if (!(view.x1 > view.x0) || !(view.y1 > view.y0) || !std::isfinite(view.x0) || !std::isfinite(view.x1) ||
      !std::isfinite(view.y0) || !std::isfinite(view.y1))
    throw InputError("view: expected finite X0 < X1 and Y0 < Y1");
  viewport_.view = view;
  region_stale_ = rgba_stale_ = true;
}

std::pair<int, int> Editor::canvas() const {
  const int w = viewport_.width, h = viewport_.height;
  if (!show_ui) return {w, h};
  return {std::max(1, w - kPanelWidth), std::max(1, h - kPlotHeight)};
}

std::vector<RegionRequest> Editor::region_requests(bool whole_window, int coarse) const {
  return requests_of(doc(), whole_window, coarse);
}

std::vector<RegionRequest> Editor::requests_of(const Document& d, bool whole_window, int coarse) const {
  RegionRequest q;
  q.mode = d.mode;
  q.split = d.split;
  if (!(d.kcurve && d.kcurve->modifying)) q.segments = d.segments;  // κ: the handle's own piece
  q.max_depth = d.max_depth;
  q.depth = d.depth_shading;
  q.view = viewport_.view;
  q.width = viewport_.width;
  q.height = viewport_.height;
  const auto [cw, ch] = whole_window ? std::pair{q.width, q.height} : canvas();
  if (cw != q.width || ch != q.height || coarse > 1) {
    const View& v = viewport_.view;
    const double sx = (v.x1 - v.x0) / q.width * coarse, sy = (v.y1 - v.y0) / q.height * coarse;
    q.width = (cw + coarse - 1) / coarse;
    q.height = (ch + coarse - 1) / coarse;
    q.view = View{v.x0, v.y1 - sy * q.height, v.x0 + sx * q.width, v.y1};
  }
  std::vector<RegionRequest> layers;
  if (d.kcurve) {  // the selected handle in its own piece; nothing else
    if (d.kcurve->modifying) {
      if (const auto h = handle_piece(d.spline, d.selected)) {
        q.point = h->local;
        layers.push_back(q);
      }
    }
    return layers;
  }
  if (d.all_points) {
    // A closed curve's repeated points are its first ones (they move together):
    // one layer each, not two overlapping copies.
    for (int k = 0; k < d.spline.unique_point_count(); ++k) {
      if (std::find(hidden_points.begin(), hidden_points.end(), k) != hidden_points.end()) continue;
      q.point = k;
      layers.push_back(q);
    }
    return layers;
  }
  q.point = d.selected;
  q.with = d.group;
  if (d.chain) {  // an anchor's handles move rigidly with it
    for (int i : translation_group(d, d.selected))
      if (i != d.selected && std::find(q.with.begin(), q.with.end(), i) == q.with.end()) q.with.push_back(i);
    q.each_piece = !q.split;  // each Bezier piece monotone on its own (docs/edit.md)
  }
  // A closed curve is never monotone over its period: as `cmr region`, one
  // point's region judges the spans it acts on unless segments are chosen.
  if (d.spline.closed() && !q.segments && !q.split && !q.each_piece)
    q.segments = closed_support_range(d.spline, q.point, q.with);
  layers.push_back(q);
  return layers;
}

BSpline Editor::region_spline() const {
  const Document& d = doc();
  if (d.kcurve && d.kcurve->modifying)
    if (auto h = handle_piece(d.spline, d.selected)) return std::move(h->piece);
  return d.spline;
}

const std::vector<const RegionResult*>& Editor::region(bool* changed) {
  if (canvas() != region_canvas_) region_stale_ = true;
  bool differs = false;
  if (region_stale_) {
    // The document's spline itself (no copy: a long spline's points are long),
    // or a kappa-curve handle's own piece.
    const Document& d = doc();
    std::optional<BSpline> piece;
    if (d.kcurve && d.kcurve->modifying) piece = region_spline();
    const BSpline& s = piece ? *piece : d.spline;
    std::vector<RegionRequest> requests = region_requests(false, 1);
    std::vector<std::vector<double>> keys;
    for (const RegionRequest& r : requests) keys.push_back(region_key(s, r));
    cache_.set_capacity(std::max<std::size_t>(16, 3 * requests.size()));
    const bool interacting = dragging_ >= 0 || panning_ || animation_.has_value();
    // (Looked up only while interacting: each lookup hashes a whole key.)
    const auto cached = [&] {
      return std::all_of(keys.begin(), keys.end(), [&](const auto& k) { return cache_.find(k) != nullptr; });
    };
    int coarse = 1;
    if (interacting && !cached()) {
      coarse = kDragCoarse;
      requests = region_requests(false, coarse);
      keys.clear();
      for (const RegionRequest& r : requests) keys.push_back(region_key(s, r));
    }
    differs = keys != region_keys_;
    if (differs) {
      static std::atomic<long> serials{0};  // unique over every editor: caches keyed by it never mix two
      region_serial_ = ++serials;
      region_.clear();
      for (std::size_t i = 0; i < requests.size(); ++i) region_.push_back(&cache_.get(s, requests[i], keys[i], &memo()));
      region_keys_ = std::move(keys);
      region_coarse_ = coarse;
      rgba_stale_ = true;
      // Why a single region is empty or full (region/region_reason.hpp), in the status line.
      if (coarse == 1 && requests.size() == 1)
        if (const auto why = cache_.reason(s, requests[0], region_keys_[0], &memo())) message = *why;
    }
    // Dragging: the full-resolution region is due when the drag ends.
    region_stale_ = coarse != 1;
    region_canvas_ = canvas();
  }
  if (changed != nullptr) *changed = differs;
  return region_;
}

const std::vector<uint8_t>& Editor::region_rgba(bool* changed) {
  bool recomputed = false;
  region(&recomputed);
  if (recomputed) rgba_stale_ = true;
  if (changed != nullptr) *changed = rgba_stale_;
  if (rgba_stale_) {
    std::vector<uint8_t>& part = region_part_;
    edit::region_rgba(region_, doc().split.has_value(), doc().depth_shading, doc().max_depth, part);
    const std::size_t w = viewport_.width, h = viewport_.height;
    const std::size_t cw = std::min<std::size_t>(region_canvas_.first, w);
    const std::size_t ch = std::min<std::size_t>(region_canvas_.second, h);
    const std::size_t c = region_coarse_, pw = region_.empty() ? 0 : region_.front()->width;
    rgba_.resize(w * h * 4);
    // Window row j shows region row j / c; pixel i of it region pixel i / c.
    parallel_for(h, 0, [&](std::size_t j) {
      uint8_t* out = &rgba_[j * w * 4];
      const bool canvas_row = j < ch && pw > 0;
      std::fill(out + (canvas_row ? cw * 4 : 0), out + w * 4, uint8_t{255});
      if (!canvas_row) return;
      const uint8_t* in = &part[(j / c) * pw * 4];
      if (c == 1) {
        std::copy_n(in, cw * 4, out);
        return;
      }
      for (std::size_t i = 0; i < cw; ++i) std::copy_n(in + (i / c) * 4, 4, out + i * 4);
    });
    rgba_stale_ = false;
  }
  return rgba_;
}

const SplineAnalysis& Editor::analysis() {
  if (analysis_stale_ || !analysis_) {
    analysis_ = verdicts(doc().spline, doc().max_depth, doc().split, doc().mode, doc().segments, &memo());
    analysis_stale_ = false;
  }
  return *analysis_;
}

const WeightRegion* Editor::weight_region_view(WeightRegionRequest* request) {
  if (!show_weight_region || doc().kcurve) return nullptr;
  if ((weight_region_stale_ && dragging_ < 0) || !weight_region_) {
    const Document& d = doc();
    WeightRegionRequest q;
    q.point = d.selected;
    const double w = d.spline.weight(d.selected);
    q.from = w == 0 ? -1 : std::min(w / 4, w * 4);
    q.to = w == 0 ? 1 : std::max(w / 4, w * 4);
    q.samples = kWeightRegionSamples;
    q.labels.mode = d.mode;
    q.labels.split = d.split;
    q.labels.segments = d.segments;
    q.labels.max_depth = d.max_depth;
    weight_region_ = weight_region(d.spline, q);
    weight_request_ = q;
    weight_region_stale_ = false;
  }
  if (request != nullptr) *request = weight_request_;
  return &*weight_region_;
}

const CurvatureEvents& Editor::events() {
  if (events_stale_) {
    events_ = curvature_events(doc().spline, doc().max_depth);
    events_stale_ = false;
  }
  return events_;
}

}  // namespace cmr::edit
