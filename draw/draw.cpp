#include "draw/draw.hpp"
#include "draw/draw_detail.hpp"
#include "draw/cairo_canvas.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <new>
#include <numbers>
#include <numeric>
#include <optional>
#include <unordered_map>

#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "io/output.hpp"

namespace cmr::draw {

using namespace detail;  // the shared helpers (draw_detail.hpp)

namespace {

// ---------------------------------------------------------------- colours --

// What one layer takes away from white; layers add up (Fig. 3's rule).
using Absorb = Rgb;

constexpr Absorb kNone{0, 0, 0};
constexpr Absorb kRed{0, 0.6, 0.6};          // white - this = (1, .4, .4)
constexpr Absorb kBlue{0.6, 0.6, 0};         // (.4, .4, 1)
constexpr Absorb kDarkRed{0.35, 0.85, 0.85};  // (.65, .15, .15)
constexpr Absorb kDarkBlue{0.85, 0.85, 0.35}; // (.15, .15, .65)
constexpr Absorb kGreen{0.6, 0.25, 0.6};      // (.4, .75, .4): each piece monotone

Rgb lerp(Rgb a, Rgb b, double s) { return {a.r + s * (b.r - a.r), a.g + s * (b.g - a.g), a.b + s * (b.b - a.b)}; }
Absorb absorb_of(Rgb c) { return {1 - c.r, 1 - c.g, 1 - c.b}; }
Rgb colour_of(Absorb a) { return {std::max(0.0, 1 - a.r), std::max(0.0, 1 - a.g), std::max(0.0, 1 - a.b)}; }

Absorb plain_absorb(uint8_t label) {
  switch (label) {
    case 1: return kRed;
    case 2: return kBlue;
    default: return kNone;  // 0 not monotone, 3 undecided
  }
}

Absorb split_absorb(uint8_t label) {
  switch (label) {
    case 1: return kRed;       // inc-inc
    case 2: return kDarkBlue;  // inc-dec: maximum at the joint
    case 3: return kDarkRed;   // dec-inc: minimum at the joint
    case 4: return kBlue;      // dec-dec
    default: return kNone;     // 0 none, 5 undecided
  }
}

Absorb piece_absorb(uint8_t label) { return label == 1 ? kGreen : kNone; }  // 0 fail, 2 undecided

/// The legend colour of a label of the picture's kind.
Absorb label_absorb(const RegionPicture& p, uint8_t label) {
  return p.each_piece ? piece_absorb(label) : p.split ? split_absorb(label) : plain_absorb(label);
}

// Fig. 7. Most pixels are decided within a few levels, so the shade saturates
// (d / (d + 2)) instead of growing linearly up to D, which would leave every
// shade but the lightest unused.
Absorb depth_absorb(uint8_t label, uint8_t depth, int max_depth) {
  const double d = std::min<double>(depth, std::max(max_depth, 0));
  const double s = d / (d + 2.0);
  switch (label) {
    case 1: return absorb_of(lerp({1, 0.72, 0.72}, {0.45, 0, 0}, s));
    case 2: return absorb_of(lerp({0.72, 0.72, 1}, {0, 0, 0.45}, s));
    default: return absorb_of(lerp({0.92, 0.92, 0.92}, {0.25, 0.25, 0.25}, s));  // not monotone, undecided
  }
}

// ----------------------------------------------------------- region panel --

/// Device coordinates of a world point inside the panel rectangle.
struct WorldMap {
  View v;
  double x, y, w, h;
  std::pair<double, double> operator()(Vec2 p) const {
    return {x + (p.x - v.x0) / (v.x1 - v.x0) * w, y + (v.y1 - p.y) / (v.y1 - v.y0) * h};
  }
};

void check_picture(const RegionPicture& p) {
  CMR_CHECK(p.spline != nullptr);
  CMR_CHECK(!p.layers.empty());
  CMR_CHECK(p.points.empty() || p.points.size() == p.layers.size());
  CMR_CHECK(!p.per_point || !p.points.empty());
  for (const RegionResult* l : p.layers) {
    CMR_CHECK(l != nullptr);
    CMR_CHECK(l->split == p.split && l->alternating == p.alternating && l->each_piece == p.each_piece);
    CMR_CHECK(l->width == p.layers[0]->width && l->height == p.layers[0]->height);
    CMR_CHECK((l->each_piece    ? l->piece_labels.size()
               : l->split       ? l->split_labels.size()
               : l->alternating ? l->alternating_labels.size()
                                : l->labels.size()) == static_cast<std::size_t>(l->width) * l->height);
    CMR_CHECK(l->depth.size() == static_cast<std::size_t>(l->width) * l->height);
  }
}

/// Per layer, what its point's colour takes from white (per-point colours;
/// empty otherwise): computed once per picture, not per pixel.
std::vector<Absorb> point_fills(const RegionPicture& p) {
  std::vector<Absorb> fills;
  if (p.per_point)
    for (int k : p.points) fills.push_back(absorb_of(lerp({1, 1, 1}, point_colour(k), 0.6)));
  return fills;
}

/// pixel_colour with the layers' fills precomputed (point_fills).
Rgb colour_at(const RegionPicture& p, const std::vector<Absorb>& fills, std::size_t index) {
  Absorb sum = kNone;
  const int W = p.layers.empty() ? 1 : std::max(1, p.layers[0]->width);
  const std::size_t i = index % W, j = index / W;
  for (std::size_t l = 0; l < p.layers.size(); ++l) {
    const RegionResult* layer = p.layers[l];
    const uint8_t label = layer->code_at(index);
    Absorb a;
    if (p.per_point) {
      // Filled where the (second part's) curvature increases, hatched where it decreases.
      const bool inc = p.split ? (label == 1 || label == 3) : label == 1;
      const bool dec = p.each_piece ? false : p.split ? (label == 2 || label == 4) : label == 2;
      if (!inc && !dec) continue;
      const double s = inc ? 1.0 : ((i + j) / 3 % 2 == 0 ? 1.0 : 0.25);
      a = {fills[l].r * s, fills[l].g * s, fills[l].b * s};
    } else {
      a = p.depth_shading ? depth_absorb(p.each_piece && label == 2 ? 0 : label, layer->depth[index], p.max_depth)
                          : label_absorb(p, label);
    }
    sum = {sum.r + a.r, sum.g + a.g, sum.b + a.b};
  }
  return colour_of(sum);
}

void draw_labels(cairo_t* cr, const RegionPicture& p, double x, double y, double w, double h) {
  const int W = p.layers[0]->width, H = p.layers[0]->height;
  Surface img = make_surface(W, H);
  cairo_surface_flush(img.get());
  unsigned char* data = cairo_image_surface_get_data(img.get());
  const int stride = cairo_image_surface_get_stride(img.get());
  auto byte = [](double c) { return static_cast<uint32_t>(std::lround(255 * std::clamp(c, 0.0, 1.0))); };
  const std::vector<Absorb> fills = point_fills(p);
  for (int j = 0; j < H; ++j) {
    auto* row = reinterpret_cast<uint32_t*>(data + static_cast<std::ptrdiff_t>(j) * stride);
    for (int i = 0; i < W; ++i) {
      const Rgb c = colour_at(p, fills, static_cast<std::size_t>(j) * W + i);
      row[i] = 0xff000000u | byte(c.r) << 16 | byte(c.g) << 8 | byte(c.b);
    }
  }
  cairo_surface_mark_dirty(img.get());
  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_scale(cr, w / W, h / H);
  cairo_set_source_surface(cr, img.get(), 0, 0);
  // Labels are exact per pixel: no smoothing between them.
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_paint(cr);
  cairo_restore(cr);
}

/// The control polygon, then the curve over it as a dense polyline.
void draw_polygon_and_curve(cairo_t* cr, const BSpline& s, const WorldMap& map) {
  set_colour(cr, {0.35, 0.35, 0.35});
  cairo_set_line_width(cr, 1.2);
  for (int i = 0; i < s.point_count(); ++i) {
    const auto [px, py] = map(s.points()[i]);
    i == 0 ? cairo_move_to(cr, px, py) : cairo_line_to(cr, px, py);
  }
  cairo_stroke(cr);
  // Enough samples per segment for a smooth look.
  set_colour(cr, {0, 0, 0});
  cairo_set_line_width(cr, 2.2);
  const int per_segment = std::max(64, 600 / s.segment_count());
  // Broken where a pole sends the curve away (CurveSampler, curvature.hpp).
  const CurveSampler sampler(s);
  std::optional<double> pen;  // the last sample drawn, while the line goes on
  for (const Segment& seg : s.segments()) {
    for (int k = 0; k <= per_segment; ++k) {
      const double t = seg.a + (seg.b - seg.a) * k / per_segment;
      const std::optional<Vec2> p = sampler.at(t);
      if (!p) {
        pen.reset();
        continue;
      }
      const auto [px, py] = map(*p);
      pen && sampler.joins(*pen, t) ? cairo_line_to(cr, px, py) : cairo_move_to(cr, px, py);
      pen = t;
    }
  }
  cairo_stroke(cr);
}

/// A moved point: a ring at its old place and an arrow to the new one.
void draw_moved(cairo_t* cr, const std::pair<Vec2, Vec2>& moved, const WorldMap& map) {
  const auto [ox, oy] = map(moved.first);
  const auto [nx, ny] = map(moved.second);
  set_colour(cr, {0.1, 0.55, 0.1});
  cairo_set_line_width(cr, 1.8);
  cairo_arc(cr, ox, oy, 5.5, 0, 2 * M_PI);
  cairo_stroke(cr);
  const double len = std::hypot(nx - ox, ny - oy);
  if (len > 12)
    arrow(cr, ox + (nx - ox) * 6 / len, oy + (ny - oy) * 6 / len, nx - (nx - ox) * 5 / len, ny - (ny - oy) * 5 / len);
}

/// "P" and the index (appended, not `"P" + ...`: GCC 12 warns falsely on that).
std::string point_name(int k) {
  std::string s = "P";
  s += std::to_string(k);
  return s;
}

/// Device-space things bucketed in square cells, so that a label box looks
/// only at its neighbourhood: placing the names of m points costs O(m), not
/// O(m^2) (`cmr region --point all` on long splines).
template <class T>
class CellGrid {
 public:
  static constexpr double kCell = 24;
  void add(double x0, double y0, double x1, double y1, const T& item) {
    for (std::int64_t i = cell(x0); i <= cell(x1); ++i)
      for (std::int64_t j = cell(y0); j <= cell(y1); ++j) cells_[key(i, j)].push_back(item);
  }
  /// Calls f(item) for the items of every cell the box touches (an item may
  /// come once per shared cell).
  template <class F>
  void near(double x0, double y0, double x1, double y1, F&& f) const {
    for (std::int64_t i = cell(x0); i <= cell(x1); ++i)
      for (std::int64_t j = cell(y0); j <= cell(y1); ++j)
        if (const auto it = cells_.find(key(i, j)); it != cells_.end())
          for (const T& item : it->second) f(item);
  }

 private:
  static std::int64_t cell(double v) { return static_cast<std::int64_t>(std::floor(std::clamp(v, -1e12, 1e12) / kCell)); }
  static std::int64_t key(std::int64_t i, std::int64_t j) { return i * 2000003 + j; }
  std::unordered_map<std::int64_t, std::vector<T>> cells_;
};

/// Points, and their names placed where they overlap no other name and as
/// little as possible of the points, the curve and the polygon: each name
/// tries eight directions (outward from the polygon's centre first) at three
/// distances and takes the least covered box; a name that would overlap one
/// already drawn is left out. Points within a pixel of each other (a closed
/// chain's ends) share one name, "P0,P12".
void draw_point_names(cairo_t* cr, const BSpline& s, const WorldMap& map, Labels& labels) {
  const int m = s.point_count();
  std::vector<std::pair<double, double>> at(m);
  for (int i = 0; i < m; ++i) at[i] = map(s.points()[i]);
  // Obstacles sampled in device space, with what covering one costs: the
  // points (200), the curve (12) and the polygon (4).
  struct Obstacle {
    double x, y, pad, cost;
  };
  CellGrid<Obstacle> obstacles;
  const auto obstacle = [&](double x, double y, double pad, double cost) {
    obstacles.add(x - pad, y - pad, x + pad, y + pad, {x, y, pad, cost});
  };
  for (const auto& [x, y] : at) obstacle(x, y, 3.5, 200);
  const CurveSampler sampler(s);
  for (const Segment& seg : s.segments())
    for (int k = 0; k <= 48; ++k) {
      const std::optional<Vec2> p = sampler.at(seg.a + (seg.b - seg.a) * k / 48);
      if (!p) continue;
      const auto [x, y] = map(*p);
      obstacle(x, y, 1, 12);
    }
  for (int i = 0; i + 1 < m; ++i)
    for (int k = 0; k <= 16; ++k)
      obstacle(at[i].first + (at[i + 1].first - at[i].first) * k / 16,
               at[i].second + (at[i + 1].second - at[i].second) * k / 16, 0, 4);
  CellGrid<std::size_t> placed;  // indices into labels.placed
  for (std::size_t i = 0; i < labels.placed.size(); ++i) {
    const TextBox& b = labels.placed[i];
    placed.add(b.x0, b.y0, b.x1, b.y1, i);
  }
  CellGrid<int> points;
  for (int i = 0; i < m; ++i) points.add(at[i].first, at[i].second, at[i].first, at[i].second, i);
  double cx = 0, cy = 0;
  for (const auto& [x, y] : at) cx += x / m, cy += y / m;
  std::vector<bool> named(m, false);
  for (int i = 0; i < m; ++i) {
    set_colour(cr, {0.1, 0.1, 0.1});
    cairo_arc(cr, at[i].first, at[i].second, 3.5, 0, 2 * M_PI);
    cairo_fill(cr);
  }
  for (int i = 0; i < m; ++i) {
    if (named[i]) continue;
    const auto [px, py] = at[i];
    std::vector<int> same;  // points within a pixel share the name
    points.near(px - 1, py - 1, px + 1, py + 1, [&](int j) {
      if (j > i && !named[j] && std::hypot(at[j].first - px, at[j].second - py) < 1 &&
          std::find(same.begin(), same.end(), j) == same.end())
        same.push_back(j);
    });
    std::sort(same.begin(), same.end());
    std::string name = point_name(i);
    for (int j : same) {
      name += ',';
      name += std::to_string(j);
      named[j] = true;
    }
    const TextBox probe = text_box(cr, 0, 0, name, 13, true);
    const double w = probe.x1 - probe.x0, h = probe.y1 - probe.y0;
    const double out = std::atan2(py - cy, px - cx);
    double best = 1e300;
    TextBox chosen;
    for (const double r : {7.0, 13.0, 21.0})
      for (int a = 0; a < 8; ++a) {
        // Alternate around the outward direction: 0, +45, -45, +90, ...
        const double angle = out + (a % 2 ? 1 : -1) * ((a + 1) / 2) * M_PI / 4;
        const double dx = std::cos(angle), dy = std::sin(angle);
        // The box's centre, so that its nearest edge is about r from the point.
        const double bx = px + dx * (r + 0.5 * w * std::fabs(dx)), by = py + dy * (r + 0.5 * h * std::fabs(dy));
        const TextBox b{bx - 0.5 * w, by - 0.5 * h, bx + 0.5 * w, by + 0.5 * h, name};
        bool free = true;
        placed.near(b.x0, b.y0, b.x1, b.y1, [&](std::size_t k) { free = free && !labels.placed[k].intersects(b); });
        if (!free) continue;
        // Each obstacle counts once although it may sit in several cells the box touches.
        std::vector<const Obstacle*> seen;
        double cost = r + 2.0 * ((a + 1) / 2);
        obstacles.near(b.x0 - 4, b.y0 - 4, b.x1 + 4, b.y1 + 4, [&](const Obstacle& o) {
          if (o.x < b.x0 - o.pad || o.x > b.x1 + o.pad || o.y < b.y0 - o.pad || o.y > b.y1 + o.pad) return;
          if (std::find(seen.begin(), seen.end(), &o) != seen.end()) return;
          seen.push_back(&o);
          cost += o.cost;
        });
        if (cost < best) best = cost, chosen = b;
      }
    if (best == 1e300) continue;  // no free place: leave the name out rather than overlap
    // Baseline start of the text whose ink box is `chosen`.
    const double tx = chosen.x0 - probe.x0, ty = chosen.y0 - probe.y0;
    set_colour(cr, {1, 1, 1});
    cairo_set_line_width(cr, 3);
    cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
    cairo_set_font_size(cr, 13);
    cairo_move_to(cr, tx, ty);
    cairo_text_path(cr, name.c_str());
    cairo_stroke(cr);  // a white halo keeps the name legible over regions and lines
    set_colour(cr, {0.1, 0.1, 0.1});
    text_at(cr, tx, ty, name, 13, true);
    placed.add(chosen.x0, chosen.y0, chosen.x1, chosen.y1, labels.placed.size());
    labels.placed.push_back(chosen);
  }
}

/// The points whose regions are shown (`cmr region`): a ring in the layer's
/// colour (per-point colours) or orange.
void draw_marked(cairo_t* cr, const RegionPicture& p, const WorldMap& map) {
  for (int k : p.points) {
    if (k < 0 || k >= p.spline->point_count()) continue;
    const auto [x, y] = map(p.spline->points()[k]);
    const Rgb c = p.per_point ? point_colour(k) : Rgb{0.95, 0.55, 0.0};
    set_colour(cr, {1, 1, 1});
    cairo_set_line_width(cr, 4.5);
    cairo_arc(cr, x, y, 7.5, 0, 2 * M_PI);
    cairo_stroke(cr);
    set_colour(cr, c);
    cairo_set_line_width(cr, 2.5);
    cairo_arc(cr, x, y, 7.5, 0, 2 * M_PI);
    cairo_stroke(cr);
  }
}

/// A legend square (or ring) at (x, y), 16 px.
void draw_swatch(cairo_t* cr, const LegendEntry& e, double x, double y) {
  if (e.ring) {
    set_colour(cr, e.colour);
    cairo_set_line_width(cr, 2.5);
    cairo_new_path(cr);
    cairo_arc(cr, x + 8, y + 8, 6, 0, 2 * M_PI);
    cairo_stroke(cr);
    return;
  }
  set_colour(cr, e.hatched ? Rgb{1, 1, 1} : e.colour);
  cairo_rectangle(cr, x, y, 16, 16);
  cairo_fill(cr);
  if (e.hatched) {
    cairo_save(cr);
    cairo_rectangle(cr, x, y, 16, 16);
    cairo_clip(cr);
    set_colour(cr, e.colour);
    cairo_set_line_width(cr, 2);
    for (double d = -16; d < 16; d += 5) {
      cairo_move_to(cr, x + d, y + 16);
      cairo_line_to(cr, x + d + 16, y);
    }
    cairo_stroke(cr);
    cairo_restore(cr);
  }
  set_colour(cr, {0.4, 0.4, 0.4});
  cairo_set_line_width(cr, 1);
  cairo_rectangle(cr, x + 0.5, y + 0.5, 15, 15);
  cairo_stroke(cr);
}

/// The legend inside a region picture: a white box in the corner that hides
/// the fewest control points and curve samples, one entry per line, when the
/// picture is large enough to keep most of it free.
void draw_inner_legend(cairo_t* cr, const RegionPicture& p, double x, double y, double w, double h) {
  if (w < 240 || h < 160) return;
  std::vector<LegendEntry> entries = legend_for(p);
  const std::size_t most = std::max<std::size_t>(2, static_cast<std::size_t>((h * 0.45 - 8) / 18));
  if (entries.size() > most) {
    const std::size_t left = entries.size() - most + 1;
    entries.resize(most - 1);
    entries.push_back({{1, 1, 1}, "... and " + std::to_string(left) + " more"});
  }
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 11);
  double tw = 0;
  for (const LegendEntry& e : entries) tw = std::max(tw, text_width(cr, e.text));
  const double bw = std::min(w - 8, 30 + tw), bh = 8 + 18 * entries.size();
  const WorldMap map{p.layers[0]->view, x, y, w, h};
  std::vector<std::pair<double, double>> things;
  for (const Vec2& q : p.spline->points()) for (int k = 0; k < 10; ++k) things.push_back(map(q));  // points weigh more
  const CurveSampler sampler(*p.spline);
  for (const Segment& seg : p.spline->segments())
    for (int k = 0; k <= 32; ++k)
      if (const std::optional<Vec2> q = sampler.at(seg.a + (seg.b - seg.a) * k / 32)) things.push_back(map(*q));
  double bx = x + 4, by = y + h - 4 - bh;
  long fewest = -1;
  const double top = y + 4 + (p.ruler ? 28 : 0);  // under a knot ruler
  for (const auto& [cx, cy] : {std::pair{x + 4, y + h - 4 - bh}, std::pair{x + w - 4 - bw, y + h - 4 - bh},
                               std::pair{x + 4, top}, std::pair{x + w - 4 - bw, top}}) {
    long n = 0;
    for (const auto& [tx, ty] : things) n += tx >= cx && tx <= cx + bw && ty >= cy && ty <= cy + bh;
    if (fewest < 0 || n < fewest) fewest = n, bx = cx, by = cy;
  }
  cairo_save(cr);
  cairo_rectangle(cr, bx, by, bw, bh);
  cairo_set_source_rgba(cr, 1, 1, 1, 0.88);
  cairo_fill_preserve(cr);
  set_colour(cr, {0.6, 0.6, 0.6});
  cairo_set_line_width(cr, 1);
  cairo_stroke(cr);
  cairo_rectangle(cr, bx, by, bw, bh);
  cairo_clip(cr);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const double ey = by + 5 + 18 * i;
    if (entries[i].text.rfind("... and", 0) != 0) draw_swatch(cr, entries[i], bx + 5, ey);
    set_colour(cr, {0, 0, 0});
    text_at(cr, bx + 26, ey + 12, entries[i].text, 11);
  }
  cairo_restore(cr);
}

/// KnotRuler: a white strip across the top, the line, the ticks, the marked
/// knot in red and the label above the line.
void draw_knot_ruler(cairo_t* cr, const KnotRuler& r, double x, double y, double w, double h) {
  if (w < kRulerMinWidth || h < kRulerMinHeight || !(r.to > r.from)) return;
  const RulerGeometry g = knot_ruler_geometry(w);
  const double gx0 = x + g.x0, gx1 = x + g.x1, gy = y + g.y;
  const auto at = [&](double u) { return gx0 + (u - r.from) / (r.to - r.from) * (gx1 - gx0); };
  cairo_save(cr);
  cairo_rectangle(cr, x + 4, y + 4, w - 8, 24);
  cairo_set_source_rgba(cr, 1, 1, 1, 0.88);
  cairo_fill_preserve(cr);
  set_colour(cr, {0.6, 0.6, 0.6});
  cairo_set_line_width(cr, 1);
  cairo_stroke(cr);
  set_colour(cr, {0.2, 0.2, 0.2});
  cairo_move_to(cr, gx0, gy + 0.5);
  cairo_line_to(cr, gx1, gy + 0.5);
  cairo_stroke(cr);
  for (std::size_t i = 0; i < r.knots.size();) {  // one tick per value, longer by its multiplicity
    std::size_t j = i;
    while (j < r.knots.size() && r.knots[j] == r.knots[i]) ++j;  // exact: a repeated knot is equal by design
    if (static_cast<int>(i) > r.marked || static_cast<int>(j) <= r.marked) {
      const double tx = std::round(at(r.knots[i])) + 0.5;
      cairo_move_to(cr, tx, gy - 3);
      cairo_line_to(cr, tx, gy + 2 + 1.5 * static_cast<double>(j - i - 1));
      cairo_stroke(cr);
    }
    i = j;
  }
  if (r.marked >= 0 && r.marked < static_cast<int>(r.knots.size())) {
    const double mx = at(r.knots[static_cast<std::size_t>(r.marked)]);
    set_colour(cr, {0.85, 0, 0});
    cairo_set_line_width(cr, 2);
    cairo_move_to(cr, mx, gy - 4);
    cairo_line_to(cr, mx, gy + 6);
    cairo_stroke(cr);
    cairo_move_to(cr, mx - 4, gy - 9);
    cairo_line_to(cr, mx + 4, gy - 9);
    cairo_line_to(cr, mx, gy - 4);
    cairo_close_path(cr);
    cairo_fill(cr);
  }
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  set_colour(cr, {0, 0, 0});
  // The label at the left, or at the right where the mark is in the left half.
  const double size = 9;
  cairo_set_font_size(cr, size);
  const double tw = text_width(cr, r.label);
  const bool right = r.marked >= 0 && r.marked < static_cast<int>(r.knots.size()) &&
                     at(r.knots[static_cast<std::size_t>(r.marked)]) < x + w / 2;
  text_at(cr, right ? x + w - 8 - tw : x + 8, y + 13, r.label, size);
  cairo_restore(cr);
}

void draw_region_panel(cairo_t* cr, const RegionPicture& p, double x, double y, double w, double h, Labels& labels) {
  check_picture(p);
  const WorldMap map{p.layers[0]->view, x, y, w, h};
  cairo_save(cr);
  cairo_rectangle(cr, x, y, w, h);
  cairo_clip(cr);
  draw_labels(cr, p, x, y, w, h);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  draw_polygon_and_curve(cr, *p.spline, map);
  if (p.moved) draw_moved(cr, *p.moved, map);
  draw_marked(cr, p, map);
  draw_point_names(cr, *p.spline, map, labels);
  if (p.legend) draw_inner_legend(cr, p, x, y, w, h);
  if (p.ruler) draw_knot_ruler(cr, *p.ruler, x, y, w, h);
  cairo_restore(cr);
  set_colour(cr, {0.5, 0.5, 0.5});
  cairo_set_line_width(cr, 1);
  cairo_rectangle(cr, x + 0.5, y + 0.5, w - 1, h - 1);
  cairo_stroke(cr);
}

// ----------------------------------------------------------- figure page --

constexpr double kMargin = 16, kGap = 12, kLabelSize = 12.5, kCaptionSize = 13, kTitleSize = 18;

/// Where everything of a figure goes; measured before drawing so that the
/// page is as tall as it needs to be.
struct FigureLayout {
  double width = 0, height = 0, side = 0;
  std::vector<std::vector<std::vector<std::string>>> labels;  ///< per row, per panel: wrapped lines
  std::vector<double> row_label_height;
  std::vector<std::string> title, caption;
  std::vector<std::pair<double, double>> legend_at;  ///< offsets from the legend's top left
  double legend_height = 0, title_height = 0;
};

/// Legend entries flow left to right and wrap like words.
void layout_legend(cairo_t* pc, const Figure& f, double text_width_px, FigureLayout& l) {
  double lx = 0, ly = 0;
  cairo_select_font_face(pc, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(pc, 12);
  for (const LegendEntry& e : f.legend) {
    const double w = 22 + text_width(pc, e.text) + 18;
    if (lx > 0 && lx + w > text_width_px) {
      lx = 0;
      ly += 22;
    }
    l.legend_at.emplace_back(lx, ly);
    lx += w;
  }
  l.legend_height = f.legend.empty() ? 0 : ly + 24;
}

FigureLayout measure_figure(const Figure& f) {
  FigureLayout l;
  l.side = f.panel_size;
  std::size_t columns = 1;
  for (const auto& row : f.rows) columns = std::max(columns, row.size());
  l.width = 2 * kMargin + columns * l.side + (columns - 1) * kGap;
  const double text_width_px = l.width - 2 * kMargin;
  Surface probe = make_surface(1, 1);
  Context pc = make_context(probe.get());
  for (const auto& row : f.rows) {
    l.labels.emplace_back();
    std::size_t most = 0;
    for (const Panel& p : row) {
      l.labels.back().push_back(wrap(pc.get(), p.label, l.side, kLabelSize));
      most = std::max(most, l.labels.back().back().size());
    }
    l.row_label_height.push_back(most * (kLabelSize + 4) + 6);
  }
  l.title = wrap(pc.get(), f.title, text_width_px, kTitleSize, true);
  l.caption = wrap(pc.get(), f.caption, text_width_px, kCaptionSize);
  layout_legend(pc.get(), f, text_width_px, l);
  l.title_height = l.title.size() * (kTitleSize + 6) + 6;
  l.height = kMargin + l.title_height;
  for (double lh : l.row_label_height) l.height += l.side + lh + kGap;
  l.height += l.legend_height + l.caption.size() * (kCaptionSize + 5) + kMargin;
  return l;
}

/// Draws the panels and their labels row by row from `y`; returns the y
/// below them. Each panel's label boxes go to *boxes when given.
double draw_figure_rows(cairo_t* c, const Figure& f, const FigureLayout& l, double y,
                        std::vector<std::vector<TextBox>>* boxes) {
  for (std::size_t r = 0; r < f.rows.size(); ++r) {
    for (std::size_t i = 0; i < f.rows[r].size(); ++i) {
      const double x = kMargin + i * (l.side + kGap);
      const Panel& p = f.rows[r][i];
      Labels labels;
      if (const auto* pic = std::get_if<RegionPicture>(&p.content))
        draw_region_panel(c, *pic, x, y, l.side, l.side, labels);
      else if (const auto* plot = std::get_if<CurvaturePlot>(&p.content))
        draw_curvature_panel(c, *plot, x, y, l.side, l.side, labels);
      else
        draw_lambda_panel(c, std::get<LambdaPlot>(p.content), x, y, l.side, l.side, labels);
      if (boxes) boxes->push_back(std::move(labels.placed));
      set_colour(c, {0, 0, 0});
      double ty = y + l.side + kLabelSize + 4;
      for (const std::string& line : l.labels[r][i]) {
        text_at(c, x, ty, line, kLabelSize);
        ty += kLabelSize + 4;
      }
    }
    y += l.side + l.row_label_height[r] + kGap;
  }
  return y;
}

void draw_legend(cairo_t* c, const Figure& f, const FigureLayout& l, double y) {
  for (std::size_t i = 0; i < f.legend.size(); ++i) {
    const LegendEntry& e = f.legend[i];
    const double x = kMargin + l.legend_at[i].first, ly0 = y + l.legend_at[i].second;
    draw_swatch(c, e, x, ly0);
    set_colour(c, {0, 0, 0});
    text_at(c, x + 22, ly0 + 13, e.text, 12);
  }
}

/// The whole figure on `c` (of layout's size): title, panels, legend, caption.
void draw_figure(cairo_t* c, const Figure& f, const FigureLayout& layout, std::vector<std::vector<TextBox>>* boxes) {
  set_colour(c, {1, 1, 1});
  cairo_paint(c);
  set_colour(c, {0, 0, 0});
  for (std::size_t i = 0; i < layout.title.size(); ++i)
    text_at(c, kMargin, kMargin + kTitleSize + i * (kTitleSize + 6), layout.title[i], kTitleSize, true);
  double y = draw_figure_rows(c, f, layout, kMargin + layout.title_height, boxes);
  draw_legend(c, f, layout, y);
  y += layout.legend_height + kCaptionSize;
  for (const std::string& line : layout.caption) {
    text_at(c, kMargin, y, line, kCaptionSize);
    y += kCaptionSize + 5;
  }
}

/// How many layers of each colouring label (1..4 with split, else 1..2) a
/// pixel has: the key of one overlap colour.
std::vector<int> overlap_key(const RegionPicture& p, std::size_t index) {
  std::vector<int> n(p.split ? 5 : p.each_piece ? 2 : 3, 0);
  for (const RegionResult* layer : p.layers) {
    const uint8_t label = layer->code_at(index);
    if (label >= 1 && label < n.size()) ++n[label];
  }
  return n;
}

/// What one region's colour means, for the legend.
const char* colour_label_meaning(bool split, bool alternating, int label, bool each_piece = false) {
  if (each_piece) return "each piece monotone on its own (either direction)";
  static const char* plain[] = {"", "curvature increasing", "curvature decreasing"};
  static const char* alternate[] = {"", "groups alternate, the first increasing (signed peak at the first joint)",
                                    "groups alternate, the first decreasing (signed dip at the first joint)"};
  if (alternating) return alternate[label];
  // By |curvature| (bezierize/extremum_terms.hpp): the signed peak is the
  // sharpest point where the curve turns left (kappa > 0), the flattest where
  // it turns right.
  static const char* splits[] = {"", "inc-inc",
                                 "inc-dec: signed peak at the joint (sharpest if turning left, flattest if right)",
                                 "dec-inc: signed dip at the joint (flattest if turning left, sharpest if right)",
                                 "dec-dec"};
  return split ? splits[label] : plain[label];
}

const char* colour_label_name(bool split, bool alternating, int label, bool each_piece = false) {
  if (each_piece) return "each-monotone";
  static const char* plain[] = {"", "increasing", "decreasing"};
  static const char* alternate[] = {"", "inc-first", "dec-first"};
  if (alternating) return alternate[label];
  static const char* splits[] = {"", "inc-inc", "inc-dec", "dec-inc", "dec-dec"};
  return split ? splits[label] : plain[label];
}

}  // namespace

RulerGeometry knot_ruler_geometry(double width) { return {12, width - 12, 22}; }

Rgb point_colour(int k) {
  static const Rgb palette[] = {{0.12, 0.47, 0.71}, {1.0, 0.5, 0.05},   {0.17, 0.63, 0.17}, {0.84, 0.15, 0.16},
                                {0.58, 0.4, 0.74},  {0.55, 0.34, 0.29}, {0.89, 0.47, 0.76}, {0.09, 0.75, 0.81}};
  if (k >= 0 && k < 8) return palette[k];
  // Further hues by the golden angle, at one saturation and value.
  const double h = std::fmod(0.61803398875 * k, 1.0) * 6, f = h - std::floor(h);
  const double v = 0.8, lo = 0.2, up = lo + (v - lo) * f, down = v - (v - lo) * f;
  switch (static_cast<int>(h)) {
    case 0: return {v, up, lo};
    case 1: return {down, v, lo};
    case 2: return {lo, v, up};
    case 3: return {lo, down, v};
    case 4: return {up, lo, v};
    default: return {v, lo, down};
  }
}

Rgb pixel_colour(const RegionPicture& p, std::size_t index) { return colour_at(p, point_fills(p), index); }

Rgb label_colour(std::uint8_t label, bool split, bool alternating, bool each_piece) {
  RegionResult one;
  one.width = one.height = 1;
  one.split = split;
  one.alternating = alternating;
  one.each_piece = each_piece;
  one.depth = {0};
  if (each_piece) one.piece_labels = {static_cast<EachPiece>(label)};
  else if (alternating) one.alternating_labels = {static_cast<Alternation>(label)};
  else if (split) one.split_labels = {static_cast<Split>(label)};
  else one.labels = {static_cast<Direction>(label)};
  RegionPicture pic;
  pic.layers = {&one};
  pic.split = split;
  pic.alternating = alternating;
  pic.each_piece = each_piece;
  return pixel_colour(pic, 0);
}

std::vector<LegendEntry> legend_for(const RegionPicture& p) {
  const auto colour = colour_of;
  std::vector<LegendEntry> l;
  if (p.per_point) {
    for (int k : p.points) l.push_back({lerp({1, 1, 1}, point_colour(k), 0.6), point_name(k)});
    const Rgb grey = lerp({1, 1, 1}, {0.3, 0.3, 0.3}, 0.6);
    l.push_back({grey, p.split ? "filled: second part increasing" : "filled: curvature increasing"});
    l.push_back({grey, p.split ? "hatched: second part decreasing" : "hatched: decreasing", true});
    l.push_back({{1, 1, 1}, "not monotone or undecided"});
    return l;
  }
  if (p.depth_shading) {
    l = {{colour(depth_absorb(1, 0, p.max_depth)), "increasing, decided at level 0"},
         {colour(depth_absorb(1, 8, p.max_depth)), "increasing, deeper"},
         {colour(depth_absorb(2, 0, p.max_depth)), "decreasing, level 0"},
         {colour(depth_absorb(2, 8, p.max_depth)), "decreasing, deeper"},
         {colour(depth_absorb(0, 0, p.max_depth)), "not monotone, level 0"},
         {colour(depth_absorb(0, 8, p.max_depth)), "not monotone, deeper"}};
  } else {
    // The colours that occur (one per combination of labels overlapping at a
    // pixel), each named by what overlaps there: the legend is what is drawn.
    check_picture(p);
    std::vector<std::vector<int>> keys;
    for (std::size_t i = 0; i < p.layers[0]->size(); ++i) {
      std::vector<int> k = overlap_key(p, i);
      if (std::all_of(k.begin(), k.end(), [](int n) { return n == 0; })) continue;
      if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(std::move(k));
    }
    std::sort(keys.begin(), keys.end(), [](const std::vector<int>& a, const std::vector<int>& b) {
      const int na = std::accumulate(a.begin(), a.end(), 0), nb = std::accumulate(b.begin(), b.end(), 0);
      return na != nb ? na < nb : std::lexicographical_compare(b.begin(), b.end(), a.begin(), a.end());
    });
    for (const std::vector<int>& k : keys) {
      Absorb sum = kNone;
      std::string text;
      for (std::size_t label = 1; label < k.size(); ++label) {
        if (k[label] == 0) continue;
        const Absorb a = label_absorb(p, static_cast<uint8_t>(label));
        sum = {sum.r + k[label] * a.r, sum.g + k[label] * a.g, sum.b + k[label] * a.b};
        if (!text.empty()) text += " + ";
        if (k[label] > 1) text += std::to_string(k[label]) + " ";
        text += colour_label_name(p.split, p.alternating, static_cast<int>(label), p.each_piece);
      }
      const int total = std::accumulate(k.begin(), k.end(), 0);
      if (total == 1)
        text = colour_label_meaning(p.split, p.alternating, static_cast<int>(std::find(k.begin(), k.end(), 1) - k.begin()),
                                    p.each_piece);
      l.push_back({colour(sum), total == 1 ? text : text + " overlap"});
    }
    l.push_back({{1, 1, 1}, p.each_piece    ? "some piece not monotone, or undecided"
                            : p.split       ? "neither part monotone, or undecided"
                            : p.alternating ? "no alternation, or undecided"
                                            : "not monotone or undecided"});
  }
  if (p.points.size() == 1) l.push_back({{0.95, 0.55, 0.0}, point_name(p.points[0]) + ", the moved point", false, true});
  if (!p.note.empty()) l.push_back({{1, 1, 1}, p.note});
  return l;
}

std::string region_png(const RegionPicture& picture) {
  check_picture(picture);
  const int W = picture.layers[0]->width, H = picture.layers[0]->height;
  Surface surface = make_surface(W, H);
  Context cr = make_context(surface.get());
  Labels labels;
  draw_region_panel(cr.get(), picture, 0, 0, W, H, labels);
  return encode_png(surface.get());
}

std::string rgba_png(int width, int height, const std::vector<std::uint8_t>& rgba) {
  if (width < 1 || height < 1 || rgba.size() != std::size_t{4} * width * height)
    throw InputError("rgba_png: " + std::to_string(rgba.size()) + " bytes are not " + std::to_string(width) + "x" +
                     std::to_string(height) + " RGBA pixels");
  Surface surface = make_surface(width, height);
  cairo_surface_flush(surface.get());
  unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  for (int j = 0; j < height; ++j) {
    auto* row = reinterpret_cast<uint32_t*>(data + static_cast<std::ptrdiff_t>(j) * stride);
    for (int i = 0; i < width; ++i) {
      const std::uint8_t* p = &rgba[4 * (static_cast<std::size_t>(j) * width + i)];
      row[i] = 0xff000000u | uint32_t{p[0]} << 16 | uint32_t{p[1]} << 8 | p[2];  // opaque ARGB32
    }
  }
  cairo_surface_mark_dirty(surface.get());
  return encode_png(surface.get());
}

void write_region_png(const std::filesystem::path& path, const RegionPicture& picture) {
  write_file_atomic(path, region_png(picture));
}

std::string figure_png(const Figure& f, std::vector<std::vector<TextBox>>* labels) {
  const FigureLayout layout = measure_figure(f);
  if (labels) labels->clear();
  return render_picture(PictureFormat::png, layout.width, layout.height,
                        [&](cairo_t* cr) { draw_figure(cr, f, layout, labels); });
}

std::string figure_svg(const Figure& f) {
  const FigureLayout layout = measure_figure(f);
  return render_picture(PictureFormat::svg, layout.width, layout.height,
                        [&](cairo_t* cr) { draw_figure(cr, f, layout, nullptr); });
}

}  // namespace cmr::draw
