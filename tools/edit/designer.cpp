#include "tools/edit/designer.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "spline/curvature.hpp"
#include "spline/errors.hpp"

namespace cmr::edit {

std::vector<std::string> read_point_names(const std::filesystem::path& path) {
  std::vector<std::string> names;
  std::ifstream in(path);
  if (!in) return names;
  try {
    const nlohmann::json doc = nlohmann::json::parse(in);
    if (!doc.is_object() || !doc.contains("point_names") || !doc["point_names"].is_array()) return names;
    for (const auto& n : doc["point_names"]) names.push_back(n.is_string() ? n.get<std::string>() : std::string());
  } catch (const nlohmann::json::exception&) {
    names.clear();
  }
  return names;
}

std::string Editor::point_name(int k) const {
  const BSpline& s = doc().spline;
  const int m = std::max(1, s.unique_point_count());
  const int i = s.closed() ? k % m : k;  // a closed curve's repeated points are its first ones
  if (i >= 0 && i < static_cast<int>(point_names.size()) && !point_names[i].empty()) return point_names[i];
  std::string name = "P";
  name += std::to_string(i);
  return name;
}

void Editor::set_point_shown(int k, bool shown) {
  if (k < 0 || k >= doc().spline.point_count())
    throw InputError("point " + std::to_string(k) + " is outside 0.." + std::to_string(doc().spline.point_count() - 1));
  std::erase(hidden_points, k);
  if (!shown) hidden_points.push_back(k);
  region_stale_ = rgba_stale_ = true;
}

std::vector<int> Editor::layer_points() const {
  std::vector<int> out;
  for (const RegionRequest& r : region_requests()) out.push_back(r.point);
  return out;
}

void Editor::set_point_xy(int k, double x, double y) {
  if (k < 0 || k >= doc().spline.point_count())
    throw InputError("point " + std::to_string(k) + " is outside 0.." + std::to_string(doc().spline.point_count() - 1));
  if (!std::isfinite(x) || !std::isfinite(y)) throw InputError("x, y: not finite numbers");
  move_point(k, {x, y});
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s placed at (%.17g, %.17g)", point_name(k).c_str(), x, y);
  message = buf;
}

namespace {

/// Square pixels, the box centred, `margin` of its size around it.
View box_view(Vec2 lo, Vec2 hi, int cw, int ch, double margin) {
  double w = hi.x - lo.x, h = hi.y - lo.y;
  const double extent = std::max({w, h, 1e-300});
  w = std::max(w, 1e-3 * extent) * (1 + 2 * margin);
  h = std::max(h, 1e-3 * extent) * (1 + 2 * margin);
  const double aspect = static_cast<double>(cw) / ch;
  if (w / h < aspect) w = h * aspect;
  else h = w / aspect;
  const double cx = 0.5 * (lo.x + hi.x), cy = 0.5 * (lo.y + hi.y);
  return {cx - 0.5 * w, cy - 0.5 * h, cx + 0.5 * w, cy + 0.5 * h};
}

void grow(std::pair<Vec2, Vec2>& box, Vec2 p) {
  box.first = {std::min(box.first.x, p.x), std::min(box.first.y, p.y)};
  box.second = {std::max(box.second.x, p.x), std::max(box.second.y, p.y)};
}

}  // namespace

void Editor::frame_box(Vec2 lo, Vec2 hi, double margin) {
  const auto [cw, ch] = canvas();
  const Viewport v{box_view(lo, hi, cw, ch, margin), cw, ch};
  viewport_ = v.resized(viewport_.width, viewport_.height);
  region_stale_ = rgba_stale_ = true;
}

void Editor::fit_view() {
  const int w = viewport_.width, h = viewport_.height;
  viewport_ = show_ui ? Viewport::fit(doc().spline, w, h, w - kPanelWidth, h - kPlotHeight)
                      : Viewport::fit(doc().spline, w, h, w, h);
  // The control polygon, the comb as it would be drawn in that view, and the
  // selected point's region within twice the polygon's view.
  const BSpline& s = doc().spline;
  std::pair<Vec2, Vec2> box{s.points()[0], s.points()[0]};
  for (const Vec2& p : s.points()) grow(box, p);
  for (const OpenedCurve& c : curves)  // a glyph's other contours
    for (const Vec2& p : c.spline.points()) grow(box, p);
  if (show_comb) {
    const Comb c = comb_geometry(s, canvas_view(*this), 1.0, comb_density);
    for (const Vec2& p : c.tips) grow(box, p);
  }
  if (!doc().all_points && !doc().kcurve) {
    try {
      if (const auto r = region_box(*this, 2.0, 96)) grow(box, r->first), grow(box, r->second);
    } catch (const InputError&) {
    }
  }
  frame_box(box.first, box.second, 0.06);
}

void Editor::fit_region() {
  const auto r = region_box(*this, 4.0, 128);
  if (!r) {
    message = point_name(doc().selected) + "'s region is empty in a view 4 times this one: nothing to frame";
    return;
  }
  std::pair<Vec2, Vec2> box = *r;
  grow(box, doc().spline.points()[doc().selected]);
  frame_box(box.first, box.second, 0.08);
  message = "framed " + point_name(doc().selected) + "'s region";
}

std::array<int, 3> bytes_of(draw::Rgb c) {
  const auto byte = [](double v) { return static_cast<int>(std::lround(255 * std::clamp(v, 0.0, 1.0))); };
  return {byte(c.r), byte(c.g), byte(c.b)};
}

View canvas_view(const Editor& e) {
  const Viewport& v = e.viewport();
  const auto [cw, ch] = e.canvas();
  const double sx = (v.view.x1 - v.view.x0) / v.width, sy = (v.view.y1 - v.view.y0) / v.height;
  return {v.view.x0, v.view.y1 - sy * ch, v.view.x0 + sx * cw, v.view.y1};
}

Comb comb_geometry(const BSpline& s, const View& view, double scale, int density) {
  Comb c;
  density = std::clamp(density, 2, 400);
  std::vector<Vec2> dirs;  // normal * kappa, away from the centre of curvature
  const CurveSampler sampler(s);
  for (const Segment& seg : s.segments()) {
    for (int i = 0; i <= density; ++i) {
      const double t = seg.a + (seg.b - seg.a) * i / density;
      const CurvatureSample k = curvature_at(s, t);
      const Vec2 d = derivative(s, t, 1);
      const double len = std::hypot(d.x, d.y);
      if (!(len > 0) || !std::isfinite(k.kappa) || !sampler.inside(k.point)) continue;
      c.feet.push_back(k.point);
      dirs.push_back(Vec2{d.y, -d.x} * (k.kappa / len));
      c.kmax = std::max(c.kmax, std::abs(k.kappa));
    }
  }
  if (!(c.kmax > 0)) {
    c.tips = c.feet;
    return c;
  }
  const double w = view.x1 - view.x0, h = view.y1 - view.y0;
  double unit = std::min(w, h) / 5 / c.kmax;
  const double mx = kCombMargin * w, my = kCombMargin * h;
  const double lx = view.x0 + mx, hx = view.x1 - mx, ly = view.y0 + my, hy = view.y1 - my;
  for (std::size_t i = 0; i < c.feet.size(); ++i) {
    const Vec2 f = c.feet[i], d = dirs[i];
    if (!(f.x > lx && f.x < hx && f.y > ly && f.y < hy)) continue;  // outside: cannot fit, not drawn in view
    if (d.x > 0) unit = std::min(unit, (hx - f.x) / d.x);
    if (d.x < 0) unit = std::min(unit, (lx - f.x) / d.x);
    if (d.y > 0) unit = std::min(unit, (hy - f.y) / d.y);
    if (d.y < 0) unit = std::min(unit, (ly - f.y) / d.y);
  }
  c.fit_unit = unit;
  c.unit = scale * unit;
  for (std::size_t i = 0; i < c.feet.size(); ++i) c.tips.push_back(c.feet[i] + dirs[i] * c.unit);
  return c;
}

int joint_continuity(const Joint& j) { return j.g2 ? 2 : j.g1 ? 1 : 0; }

std::optional<CurvePick> pick_curve(const BSpline& s, const Viewport& viewport, double x, double y, double radius) {
  const CurveSampler sampler(s);
  double best_t = 0, best_d = radius;
  bool found = false;
  const auto dist = [&](double t) -> double {
    const std::optional<Vec2> p = sampler.at(t);
    if (!p) return INFINITY;
    const Vec2 q = viewport.to_screen(*p);
    return std::hypot(q.x - x, q.y - y);
  };
  constexpr int kSamples = 96;
  double step = 0;
  for (const Segment& seg : s.segments()) {
    for (int i = 0; i <= kSamples; ++i) {
      const double t = seg.a + (seg.b - seg.a) * i / kSamples;
      if (const double d = dist(t); d <= best_d) best_d = d, best_t = t, found = true, step = (seg.b - seg.a) / kSamples;
    }
  }
  if (!found) return std::nullopt;
  // Golden-section refinement in the sample's neighbourhood.
  double a = std::max(s.domain_begin(), best_t - step), b = std::min(s.domain_end(), best_t + step);
  for (int it = 0; it < 40; ++it) {
    const double m1 = a + (b - a) * 0.382, m2 = a + (b - a) * 0.618;
    if (dist(m1) < dist(m2)) b = m2;
    else a = m1;
  }
  const double t = dist(0.5 * (a + b)) < best_d ? 0.5 * (a + b) : best_t;
  const CurvatureSample c = curvature_at(s, t);
  return CurvePick{t, c.point, c.kappa};
}

std::optional<std::pair<Vec2, Vec2>> region_box(const Editor& e, double zoom, int pixels) {
  std::vector<RegionRequest> q = e.region_requests();
  if (q.size() != 1) return std::nullopt;
  const View c = canvas_view(e);
  const double cx = 0.5 * (c.x0 + c.x1), cy = 0.5 * (c.y0 + c.y1);
  const double hw = 0.5 * (c.x1 - c.x0) * zoom, hh = 0.5 * (c.y1 - c.y0) * zoom;
  RegionRequest r = q.front();
  r.view = View{cx - hw, cy - hh, cx + hw, cy + hh};
  r.width = std::max(8, pixels);
  r.height = std::max(8, static_cast<int>(std::lround(pixels * hh / hw)));
  r.depth = false;
  const RegionResult res = compute_regions(e.region_spline(), {r}, &e.memo()).front();
  std::optional<std::pair<Vec2, Vec2>> box;
  const double px = 2 * hw / r.width, py = 2 * hh / r.height;
  for (int j = 0; j < res.height; ++j)
    for (int i = 0; i < res.width; ++i) {
      if (!res.in_region(static_cast<std::size_t>(j) * res.width + i)) continue;
      const Vec2 lo{r.view->x0 + i * px, r.view->y1 - (j + 1) * py}, hi{lo.x + px, lo.y + py};
      if (!box) box = std::pair{lo, hi};
      else grow(*box, lo), grow(*box, hi);
    }
  return box;
}

Legend region_legend(Editor& e) {
  Legend l;
  const Document& d = e.doc();
  const std::string who = e.point_name(d.selected);
  const bool each_piece = d.chain && !d.split && !d.kcurve;
  if (d.kcurve && !d.kcurve->modifying) l.title = "kappa-curve: click points (no region yet)";
  else if (d.kcurve) l.title = "where " + who + " may go without a new curvature extremum in its cubic piece";
  else if (d.all_points) l.title = "every point's region overlapped (each outlined in its point's hue)";
  else if (d.split) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "split at joint %d: where %s may go so that the curvature extremum sits at knot u=%.6g",
                  *d.split, who.c_str(), d.spline.segments()[*d.split].a);
    l.title = buf;
  } else if (each_piece)
    l.title = "Bezier chain: where " + who + " may go so that every piece's curvature is monotone on its own";
  else if (d.mode == Mode::cmr)
    l.title = "CMR: where " + who + " may go so that the curvature is monotone and the curve has no inflection";
  else
    l.title = "CMRWI: where " + who + " may go so that the curvature is monotone (inflections allowed)";
  if (d.depth_shading) l.title += "; shading: the level at which each pixel was decided (Fig. 7)";

  const std::vector<const RegionResult*>& layers = e.region();
  // What the layers give (every pixel scanned) is remembered until they change.
  struct Cached {
    long serial = -1;
    std::vector<draw::LegendEntry> entries;
    std::vector<bool> any;  ///< per layer: some pixel inside
  };
  static thread_local Cached cache;
  if (cache.serial != e.region_serial()) {
    cache = {e.region_serial(), {}, {}};
    if (!layers.empty()) {
      const BSpline shown = e.region_spline();
      draw::RegionPicture p;
      p.spline = &shown;
      p.layers = layers;
      p.split = d.split.has_value();
      p.alternating = layers.front()->alternating;
      p.each_piece = layers.front()->each_piece;
      p.depth_shading = d.depth_shading;
      p.max_depth = d.max_depth;
      cache.entries = draw::legend_for(p);
    }
    for (const RegionResult* r : layers) {
      bool any = false;
      for (std::size_t j = 0; j < r->size() && !any; ++j) any = r->in_region(j);
      cache.any.push_back(any);
    }
  }
  {
    const std::vector<draw::LegendEntry>& entries = cache.entries;
    for (std::size_t i = 0; i < entries.size(); ++i) {
      const draw::LegendEntry& en = entries[i];
      std::string text = en.text;
      if (text == "curvature increasing") text = "curvature increasing along the curve";
      if (text == "curvature decreasing") text = "curvature decreasing along the curve";
      // Depth shading comes in pairs (level 0, deeper): one gradient each.
      if (d.depth_shading && i + 1 < entries.size() && i % 2 == 0) {
        std::string name = text.substr(0, text.find(','));
        if (name == "decreasing" || name == "increasing") name = "curvature " + name;
        l.lines.push_back({LegendLine::Kind::gradient, en.colour, entries[i + 1].colour,
                           name + " (light: decided at level 0, dark: at level " + std::to_string(d.max_depth) + ")"});
        ++i;
        continue;
      }
      l.lines.push_back({LegendLine::Kind::swatch, en.colour, en.colour, text});
    }
  }
  if (d.all_points) {
    const std::vector<int> points = e.layer_points();
    for (std::size_t i = 0; i < points.size() && i < cache.any.size(); ++i) {
      const int k = points[i];
      l.lines.push_back({LegendLine::Kind::outline, draw::point_colour(k), draw::point_colour(k),
                         e.point_name(k) + "'s region" + (cache.any[i] ? "" : " (none in this view)"), k});
    }
  }
  if (e.show_overlay) {
    const draw::Rgb orange{230 / 255.0, 120 / 255.0, 0}, cyan{0, 160 / 255.0, 200 / 255.0},
        purple{140 / 255.0, 0, 160 / 255.0};
    l.lines.push_back({LegendLine::Kind::dot, orange, orange, "sharpest (max |curvature|)"});
    l.lines.push_back({LegendLine::Kind::dot, cyan, cyan, "flattest (min)", -1, true});
    l.lines.push_back({LegendLine::Kind::square, purple, purple, "inflection"});
    if (e.show_comb) {
      const draw::Rgb green{60 / 255.0, 140 / 255.0, 60 / 255.0};
      l.lines.push_back({LegendLine::Kind::line, green, green, "comb (|curvature|)", -1, true});
    }
    if (d.spline.segment_count() > 1) {
      l.lines.push_back({LegendLine::Kind::diamond, {0.1, 0.65, 0.1}, {}, "joints: G2"});
      l.lines.push_back({LegendLine::Kind::diamond, {0.95, 0.75, 0.0}, {}, "G1 (curvature jumps)", -1, true});
      l.lines.push_back({LegendLine::Kind::diamond, {0.85, 0.1, 0.1}, {}, "G0", -1, true});
    }
  }
  return l;
}

std::vector<PlacedLabel> place_labels(const std::vector<Vec2>& pts, const std::vector<Vec2>& sizes,
                                      float marker_radius) {
  std::vector<PlacedLabel> placed;
  const auto overlaps = [&](float x, float y, float w, float h, int self) {
    for (const PlacedLabel& p : placed)
      if (x < p.x + p.w && p.x < x + w && y < p.y + p.h && p.y < y + h) return true;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (static_cast<int>(i) == self) continue;
      const float px = static_cast<float>(pts[i].x), py = static_cast<float>(pts[i].y);
      if (px + marker_radius > x && px - marker_radius < x + w && py + marker_radius > y && py - marker_radius < y + h)
        return true;
    }
    return false;
  };
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const float px = static_cast<float>(pts[i].x), py = static_cast<float>(pts[i].y);
    const float w = static_cast<float>(sizes[i].x), h = static_cast<float>(sizes[i].y), g = marker_radius + 2;
    const float cand[8][2] = {{px + g, py - h - 2}, {px + g, py + 2},         {px - g - w, py - h - 2},
                              {px - g - w, py + 2}, {px - w / 2, py - g - h}, {px - w / 2, py + g},
                              {px + g, py - h / 2}, {px - g - w, py - h / 2}};
    for (const auto& c : cand)
      if (!overlaps(c[0], c[1], w, h, static_cast<int>(i))) {
        placed.push_back({static_cast<int>(i), c[0], c[1], w, h});
        break;
      }
  }
  return placed;
}

}  // namespace cmr::edit

namespace cmr::edit {

bool Editor::in_selected_region(Vec2 p) const {
  const Document& d = doc();
  if (d.all_points || d.kcurve) return false;
  const std::vector<RegionRequest> q = region_requests();
  if (q.size() != 1) return false;
  RegionRequest r = q.front();
  r.depth = false;
  return in_region(memo().make(region_spline(), r).classify(p), r);
}

Vec2 Editor::constrained_target(Vec2 from, Vec2 to) const {
  const Document& d = doc();
  if (d.all_points || d.kcurve) return to;
  const std::vector<RegionRequest> q = region_requests();
  if (q.size() != 1) return to;
  RegionRequest r = q.front();
  r.depth = false;
  try {
    // The region of P_k does not depend on where P_k stands: one problem.
    const RegionProblem problem = memo().make(region_spline(), r);
    const auto inside = [&](Vec2 p) { return in_region(problem.classify(p), r); };
    if (inside(to) || !inside(from)) return to;
    double in = 0, out = 1;  // from + (to - from) * s: inside at `in`, outside at `out`
    for (int i = 0; i < kConstrainSteps; ++i) {
      const double mid = 0.5 * (in + out);
      (inside(from + (to - from) * mid) ? in : out) = mid;
    }
    return from + (to - from) * in;  // certified inside (in == 0: where it stands)
  } catch (const InputError&) {
    return to;
  }
}

}  // namespace cmr::edit
