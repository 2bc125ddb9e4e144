#include "tools/edit/ui.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <set>

#include "design/kcurve.hpp"
#include "tools/edit/designer.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "tools/field_flags.hpp"

namespace cmr::edit {
namespace {

constexpr int kCurveSamplesPerSegment = 48;
constexpr int kCombTeethPerSegment = 24;
constexpr int kPlotSamples = 400;
constexpr float kPanelWidth = Editor::kPanelWidth;
constexpr ImU32 kCurveColour = IM_COL32(20, 20, 20, 255);
constexpr ImU32 kPolygonColour = IM_COL32(90, 90, 90, 255);
constexpr ImU32 kCombColour = IM_COL32(60, 140, 60, 200);
constexpr ImU32 kMaximumColour = IM_COL32(230, 120, 0, 255);
constexpr ImU32 kMinimumColour = IM_COL32(0, 160, 200, 255);
constexpr ImU32 kInflectionColour = IM_COL32(140, 0, 160, 255);
constexpr ImU32 kIncreasingColour = IM_COL32(215, 30, 30, 255);
constexpr ImU32 kDecreasingColour = IM_COL32(30, 50, 215, 255);

ImVec2 screen(const Editor& e, Vec2 w) {
  const Vec2 s = e.viewport().to_screen(w);
  return {static_cast<float>(s.x), static_cast<float>(s.y)};
}

/// Runs an action from a widget; a bad value becomes the status line.
template <class F>
void act(Editor& e, F&& f) {
  try {
    f();
  } catch (const InputError& err) {
    e.message = cli::shown_message(err);
  }
}

void draw_curve(Editor& e, ImDrawList* dl) {
  const BSpline& s = e.doc().spline;
  const CurveSampler sampler(s);  // broken near a pole (spline/curvature.hpp)
  std::vector<ImVec2> line;
  double last = 0;
  const auto flush = [&] {
    if (line.size() > 1) dl->AddPolyline(line.data(), static_cast<int>(line.size()), kCurveColour, 0, 2.0f);
    line.clear();
  };
  for (const Segment& seg : s.segments()) {
    for (int i = 0; i <= kCurveSamplesPerSegment; ++i) {
      const double t = seg.a + (seg.b - seg.a) * i / kCurveSamplesPerSegment;
      const std::optional<Vec2> p = sampler.at(t);
      if (!p || (!line.empty() && !sampler.joins(last, t))) flush();
      if (p) line.push_back(screen(e, *p)), last = t;
    }
  }
  flush();
}

ImU32 colour_u32(draw::Rgb c, int alpha = 255) {
  const auto b = bytes_of(c);
  return IM_COL32(b[0], b[1], b[2], alpha);
}

/// The comb fitted to the canvas's view (designer.hpp's comb_geometry), its
/// outline, the certified extrema and inflections, and the joints by
/// continuity.
void draw_comb_of(Editor& e, ImDrawList* dl, const BSpline& s) {
  const Comb c = comb_geometry(s, canvas_view(e), e.comb_scale, e.comb_density);
  for (std::size_t i = 0; i < c.feet.size(); ++i) {
    dl->AddLine(screen(e, c.feet[i]), screen(e, c.tips[i]), kCombColour);
    if (e.comb_outline && i > 0 && c.feet.size() > 1)
      dl->AddLine(screen(e, c.tips[i - 1]), screen(e, c.tips[i]), IM_COL32(30, 100, 30, 255), 1.5f);
  }
}

/// The edited curve's comb and, with comb_all_curves, every other opened
/// curve's (each fitted to the view on its own).
void draw_comb(Editor& e, ImDrawList* dl) {
  draw_comb_of(e, dl, e.doc().spline);
  if (!e.comb_all_curves) return;
  for (int c = 0; c < static_cast<int>(e.curves.size()); ++c)
    if (c != e.active_curve) draw_comb_of(e, dl, e.curves[c].spline);
}

void draw_marks(Editor& e, ImDrawList* dl) {
  const BSpline& s = e.doc().spline;
  const CurvatureEvents& ev = e.events();
  for (double t : ev.maxima) dl->AddCircleFilled(screen(e, evaluate(s, t)), 6, kMaximumColour);
  for (double t : ev.minima) dl->AddCircleFilled(screen(e, evaluate(s, t)), 6, kMinimumColour);
  for (double t : ev.inflections) {
    const ImVec2 p = screen(e, evaluate(s, t));
    dl->AddRectFilled({p.x - 5, p.y - 5}, {p.x + 5, p.y + 5}, kInflectionColour);
  }
  // Joints by continuity (bezierize/analyze's joints): G2 green, G1 amber, G0 red.
  const SplineAnalysis& a = e.analysis();
  std::vector<Joint> joints = a.joints;
  if (a.seam) joints.push_back(*a.seam);
  static const ImU32 colours[3] = {IM_COL32(217, 26, 26, 255), IM_COL32(242, 191, 0, 255), IM_COL32(26, 166, 26, 255)};
  for (const Joint& j : joints) {
    const ImVec2 p = screen(e, evaluate(s, j.knot));
    const float r = 6;
    dl->AddQuadFilled({p.x, p.y - r}, {p.x + r, p.y}, {p.x, p.y + r}, {p.x - r, p.y}, colours[joint_continuity(j)]);
    dl->AddQuad({p.x, p.y - r}, {p.x + r, p.y}, {p.x, p.y + r}, {p.x - r, p.y}, IM_COL32(0, 0, 0, 255));
  }
}

/// Every point overlapped: each layer's region outlined in its point's hue
/// (the edges between inside and outside pixels, in runs; recomputed when
/// the layers change).
void draw_outlines(Editor& e, ImDrawList* dl) {
  if (!e.doc().all_points) return;
  struct Edge {
    ImVec2 a, b;
    ImU32 colour;
  };
  static long serial = -1;
  static std::vector<Edge> edges;
  const std::vector<const RegionResult*>& layers = e.region();
  if (serial != e.region_serial()) {
    serial = e.region_serial();
    edges.clear();
    const std::vector<int> points = e.layer_points();
    const float c = static_cast<float>(e.region_coarse());
    for (std::size_t l = 0; l < layers.size() && l < points.size(); ++l) {
      const RegionResult& r = *layers[l];
      const ImU32 col = colour_u32(draw::point_colour(points[l]));
      // Inside or not, once per pixel, with a border of outside pixels (the
      // edge scans below read each pixel up to four times).
      const int W = r.width + 2;
      std::vector<std::uint8_t> inside(static_cast<std::size_t>(W) * (r.height + 2), 0);
      for (int j = 0; j < r.height; ++j)
        for (int i = 0; i < r.width; ++i)
          inside[static_cast<std::size_t>(j + 1) * W + i + 1] = r.in_region(static_cast<std::size_t>(j) * r.width + i);
      const auto in = [&](int i, int j) { return inside[static_cast<std::size_t>(j + 1) * W + i + 1] != 0; };
      for (int j = 0; j <= r.height; ++j) {  // horizontal edges above row j, in runs
        int run = -1;
        for (int i = 0; i <= r.width; ++i) {
          const bool edge = i < r.width && in(i, j) != in(i, j - 1);
          if (edge && run < 0) run = i;
          if (!edge && run >= 0) {
            edges.push_back({{run * c, j * c}, {i * c, j * c}, col});
            run = -1;
          }
        }
      }
      for (int i = 0; i <= r.width; ++i) {  // vertical edges left of column i
        int run = -1;
        for (int j = 0; j <= r.height; ++j) {
          const bool edge = j < r.height && in(i, j) != in(i - 1, j);
          if (edge && run < 0) run = j;
          if (!edge && run >= 0) {
            edges.push_back({{i * c, run * c}, {i * c, j * c}, col});
            run = -1;
          }
        }
      }
    }
  }
  for (const Edge& x : edges) dl->AddLine(x.a, x.b, x.colour, 2.0f);
}

/// The curves opened beside the active one (a glyph's other contours, an
/// SVG's other paths): grey, with their points; a click on one edits it.
void draw_other_curves(Editor& e, ImDrawList* dl, std::vector<Vec2>& at, std::vector<Vec2>& sizes,
                       std::vector<std::string>& names) {
  for (int c = 0; c < static_cast<int>(e.curves.size()); ++c) {
    if (c == e.active_curve) continue;
    const OpenedCurve& oc = e.curves[c];
    const BSpline& s = oc.spline;
    const CurveSampler sampler(s);
    std::vector<ImVec2> line;
    for (const Segment& seg : s.segments())
      for (int i = 0; i <= kCurveSamplesPerSegment; ++i)
        if (const auto p = sampler.at(seg.a + (seg.b - seg.a) * i / kCurveSamplesPerSegment)) line.push_back(screen(e, *p));
    if (line.size() > 1) dl->AddPolyline(line.data(), static_cast<int>(line.size()), IM_COL32(110, 110, 110, 255), 0, 1.5f);
    const std::vector<Vec2>& pts = s.points();
    for (std::size_t i = 1; i < pts.size(); ++i) dl->AddLine(screen(e, pts[i - 1]), screen(e, pts[i]), IM_COL32(170, 170, 170, 255));
    const int n = s.closed() ? s.unique_point_count() : s.point_count();
    const bool source = !oc.font_point.empty();
    const std::string prefix = oc.name + "/";
    for (int i = 0; i < n; ++i) {
      if (source && i < static_cast<int>(oc.font_point.size()) && oc.font_point[i] < 0) continue;  // a line's added point
      const ImVec2 p = screen(e, pts[i]);
      dl->AddCircleFilled(p, 4.0f, IM_COL32(235, 235, 235, 255));
      dl->AddCircle(p, 4.0f, IM_COL32(110, 110, 110, 255), 0, 1.0f);
      std::string name = "P";  // (built with +=: GCC 12 warns falsely on "P" + std::to_string)
      if (i < static_cast<int>(oc.point_names.size())) name = oc.point_names[i];
      else name += std::to_string(i);
      // A font source's names short on the canvas ("p3"; the full name on hover).
      if (source && name.size() > prefix.size() && name.compare(0, prefix.size(), prefix) == 0)
        name.erase(0, prefix.size());
      const ImVec2 size = ImGui::CalcTextSize(name.c_str());
      at.push_back({p.x, p.y});
      sizes.push_back({size.x, size.y});
      names.push_back(std::move(name));
    }
  }
}

void draw_points(Editor& e, ImDrawList* dl) {
  const Document& d = e.doc();
  const std::vector<Vec2>& pts = d.spline.points();
  for (std::size_t i = 1; i < pts.size(); ++i) dl->AddLine(screen(e, pts[i - 1]), screen(e, pts[i]), kPolygonColour);
  // A closed curve's repeated points are its first ones: drawn and named once.
  const int n = d.spline.closed() ? d.spline.unique_point_count() : d.spline.point_count();
  std::vector<Vec2> at, sizes;
  std::vector<std::string> names;
  for (int i = 0; i < n; ++i) {
    if (!e.movable(i)) continue;  // a font source's line point: neither drawn nor dragged
    const ImVec2 p = screen(e, pts[i]);
    const bool grouped = std::find(d.group.begin(), d.group.end(), i) != d.group.end();
    const ImU32 fill = i == d.selected ? IM_COL32(230, 30, 30, 255)
                                       : (grouped ? IM_COL32(240, 150, 0, 255) : IM_COL32(255, 255, 255, 255));
    dl->AddCircleFilled(p, 5.5f, fill);
    dl->AddCircle(p, 5.5f, IM_COL32(0, 0, 0, 255), 0, 1.5f);
    names.push_back(e.short_point_name(i));
    const ImVec2 size = ImGui::CalcTextSize(names.back().c_str());
    at.push_back({p.x, p.y});
    sizes.push_back({size.x, size.y});
  }
  const std::size_t active = names.size();
  draw_other_curves(e, dl, at, sizes, names);
  // Names that would overprint another name or a point are left out (hover
  // shows them); the active curve's are placed first.
  for (const PlacedLabel& l : place_labels(at, sizes, 6)) {
    const bool mine = static_cast<std::size_t>(l.point) < active;
    dl->AddRectFilled({l.x - 1, l.y}, {l.x + l.w + 1, l.y + l.h}, IM_COL32(255, 255, 255, 170));
    dl->AddText({l.x, l.y}, mine ? IM_COL32(0, 0, 0, 255) : IM_COL32(110, 110, 110, 255), names[l.point].c_str());
  }
}

/// κ-curve mode: its interpolation points (squares) and, modifying, the
/// piece whose region is shown.
void draw_kcurve(Editor& e, ImDrawList* dl) {
  const Document& d = e.doc();
  if (!d.kcurve) return;
  for (const Vec2& p : d.kcurve->points) {
    const ImVec2 s = screen(e, p);
    dl->AddRect({s.x - 6, s.y - 6}, {s.x + 6, s.y + 6}, IM_COL32(0, 120, 0, 255), 0, 0, 2);
  }
}

void kcurve_controls(Editor& e) {
  const Document& d = e.doc();
  if (!d.kcurve) {
    if (ImGui::Button("kappa-curve: click points")) act(e, [&] { e.set_kcurve(true); });
    return;
  }
  if (!d.kcurve->modifying) {
    bool closed = d.kcurve->closed;
    if (ImGui::Checkbox("closed", &closed)) act(e, [&] { e.set_kcurve_closed(closed); });
    ImGui::SameLine();
    if (ImGui::Button("modify (G1 handle pairs)")) act(e, [&] { e.kcurve_modify(); });
  } else {
    ImGui::TextWrapped("region: the selected handle within its cubic piece (no new extremum there)");
  }
  ImGui::SameLine();
  if (ImGui::Button("leave kappa mode")) act(e, [&] { e.set_kcurve(false); });
}

/// Which segments the region judges: all, or first..last.
void segment_range(Editor& e) {
  const Document& d = e.doc();
  const int n = d.spline.segment_count();
  bool some = d.segments.has_value();
  if (ImGui::Checkbox("judge segments", &some))
    act(e, [&] { e.set_segments(some ? std::optional<SegmentRange>(SegmentRange{0, n - 1}) : std::nullopt); });
  if (const auto support = e.closed_support())  // a closed curve's default (Editor::closed_support)
    ImGui::TextWrapped("closed curve: P%d's region judges segments %d..%d, the spans it acts on", d.selected,
                       support->first, support->last);
  if (!d.segments) return;
  int range[2] = {d.segments->first, d.segments->last};
  ImGui::SameLine();
  ImGui::SetNextItemWidth(120);
  if (ImGui::DragInt2("first..last", range, 0.05f, 0, n - 1) && range[0] <= range[1])
    act(e, [&] { e.set_segments(SegmentRange{range[0], range[1]}); });
}

/// The region of the selected point's weight (Editor::weight_region_view):
/// a strip over [w/4, 4w] in the canvas's colours, the current weight
/// marked, and the monotone stretches as text.
void weight_strip(Editor& e) {
  WeightRegionRequest q;
  const WeightRegion* r = nullptr;
  act(e, [&] { r = e.weight_region_view(&q); });
  if (r == nullptr) return;
  const ImVec2 o = ImGui::GetCursorScreenPos();
  const float width = ImGui::GetContentRegionAvail().x, height = 14;
  const int columns = std::max(1, static_cast<int>(width));
  RegionResult strip = r->kind;
  strip.width = columns;
  strip.height = 1;
  strip.depth.assign(columns, 0);
  const auto label_at = [&](double w) {
    for (const WeightInterval& iv : r->intervals)
      if (w <= iv.to) return iv.label;
    return r->intervals.back().label;
  };
  for (int i = 0; i < columns; ++i) {
    const std::uint8_t l = label_at(q.from + (q.to - q.from) * (i + 0.5) / columns);
    if (strip.split) strip.split_labels.push_back(static_cast<Split>(l));
    else strip.labels.push_back(static_cast<Direction>(l));
  }
  const std::vector<uint8_t> rgba = region_rgba({&strip}, strip.split, false, q.labels.max_depth);
  ImDrawList* dl = ImGui::GetWindowDrawList();
  for (int i = 0; i < columns; ++i)
    dl->AddRectFilled({o.x + i, o.y}, {o.x + i + 1, o.y + height},
                      IM_COL32(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2], 255));
  for (const WeightInterval& iv : r->intervals)  // a pole: hatched
    if (iv.pole) {
      const float x0 = o.x + static_cast<float>((iv.from - q.from) / (q.to - q.from)) * width;
      const float x1 = o.x + static_cast<float>((iv.to - q.from) / (q.to - q.from)) * width;
      dl->PushClipRect({x0, o.y}, {x1 + 1, o.y + height}, true);
      for (float x = x0 - height; x < x1; x += 5) dl->AddLine({x, o.y + height}, {x + height, o.y}, IM_COL32(60, 60, 60, 255));
      dl->PopClipRect();
    }
  dl->AddRect(o, {o.x + width, o.y + height}, IM_COL32(0, 0, 0, 255));
  const double w = e.doc().spline.weight(q.point);
  const float x = o.x + static_cast<float>((w - q.from) / (q.to - q.from)) * width;
  dl->AddLine({x, o.y - 2}, {x, o.y + height + 2}, kMaximumColour, 2.0f);
  ImGui::Dummy({width, height});
  const auto num = [](double value) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", value);
    return std::string(buf);
  };
  std::string text = "w in [" + num(q.from) + ", " + num(q.to) + "]:";
  bool any = false;
  for (const WeightInterval& iv : r->intervals) {
    const std::string name = r->label_name(iv.label);
    if (iv.pole) text += " pole " + num(iv.from) + ".." + num(iv.to);
    if (iv.label == 0 || name == "undecided") continue;  // white in the strip
    text += " " + name + " " + num(iv.from) + ".." + num(iv.to);
    any = true;
  }
  if (!any) text += " none monotone";
  ImGui::TextWrapped("%s", text.c_str());
}

/// Typed coordinates (and weight) of the selected point: Enter applies the
/// value exactly as typed (ImGui parses it with %lf: the nearest double).
void typed_fields(Editor& e, const UiInfo& info) {
  const Document& d = e.doc();
  if (d.kcurve) return;
  const Vec2 p = d.spline.points()[d.selected];
  double x = p.x, y = p.y, w = d.spline.weight(d.selected);
  const ImGuiInputTextFlags flags = ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_CharsScientific;
  const auto remember = [&](const char* name) {
    if (info.fields == nullptr) return;
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    (*info.fields)[name] = {a.x, a.y, b.x, b.y};
  };
  ImGui::SetNextItemWidth(120);
  if (ImGui::InputDouble("x", &x, 0, 0, "%.17g", flags)) act(e, [&] { e.set_point_xy(d.selected, x, p.y); });
  remember("x");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(120);
  if (ImGui::InputDouble("y", &y, 0, 0, "%.17g", flags)) act(e, [&] { e.set_point_xy(d.selected, p.x, y); });
  remember("y");
  ImGui::SetNextItemWidth(120);
  if (ImGui::InputDouble("w (typed weight)", &w, 0, 0, "%.17g", flags)) act(e, [&] { e.set_weight(d.selected, w); });
  remember("w");
}

void controls(Editor& e, const UiInfo& info) {
  const Document& d = e.doc();
  int mode = d.mode == Mode::cmr ? 1 : 0;
  if (ImGui::RadioButton("CMRWI", &mode, 0)) act(e, [&] { e.set_mode(Mode::cmrwi); });
  ImGui::SameLine();
  if (ImGui::RadioButton("CMR (no inflection)", &mode, 1)) act(e, [&] { e.set_mode(Mode::cmr); });
  int depth = d.max_depth;
  if (ImGui::SliderInt("depth D", &depth, 0, kMaxDepth)) act(e, [&] { e.set_depth(depth); });
  bool shading = d.depth_shading, all = d.all_points, chain = d.chain;
  if (ImGui::Checkbox("depth shading (Fig. 7)", &shading)) act(e, [&] { e.set_depth_shading(shading); });
  if (ImGui::Checkbox("all points overlapped", &all)) act(e, [&] { e.set_all_points(all); });
  if (d.all_points) {  // which points' regions are drawn (each outlined in its hue)
    const int n = d.spline.unique_point_count();
    for (int k = 0; k < n; ++k) {
      bool shown = std::find(e.hidden_points.begin(), e.hidden_points.end(), k) == e.hidden_points.end();
      ImGui::PushID(k);
      const auto b = bytes_of(draw::point_colour(k));
      ImGui::PushStyleColor(ImGuiCol_CheckMark, IM_COL32(b[0], b[1], b[2], 255));
      if (ImGui::Checkbox(e.point_name(k).c_str(), &shown)) act(e, [&] { e.set_point_shown(k, shown); });
      ImGui::PopStyleColor();
      ImGui::PopID();
      if (k % 4 != 3 && k + 1 < n) ImGui::SameLine();
    }
  }
  if (ImGui::Checkbox("chain (G1)", &chain)) act(e, [&] { e.set_chain(chain); });
  ImGui::SameLine();
  ImGui::Checkbox("keep in region", &e.constrain_drag);
  ImGui::SameLine();
  ImGui::Checkbox("legend", &e.show_legend);
  if (e.show_legend) ImGui::Checkbox("legend in this panel", &e.legend_docked);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("a dragged point inside its region stops at its boundary (certified positions only)");
  const int joints = d.spline.segment_count() - 1;
  const std::string current = d.split ? "joint " + std::to_string(*d.split) : "none";
  if (ImGui::BeginCombo("split", current.c_str())) {
    if (ImGui::Selectable("none", !d.split)) act(e, [&] { e.set_split(std::nullopt); });
    for (int j = 1; j <= joints; ++j) {
      const std::string label = "joint " + std::to_string(j) + " (extremum at u=" +
                                std::to_string(d.spline.segments()[j].a).substr(0, 6) + ")";
      if (ImGui::Selectable(label.c_str(), d.split == j)) act(e, [&] { e.set_split(j); });
    }
    ImGui::EndCombo();
  }
  segment_range(e);
  ImGui::Checkbox("comb", &e.show_comb);
  if (e.curves.size() > 1) {
    ImGui::SameLine();
    ImGui::Checkbox("every contour", &e.comb_all_curves);
  }
  ImGui::SameLine();
  float scale = static_cast<float>(e.comb_scale);
  ImGui::SetNextItemWidth(80);
  // 1: the comb fits the view (designer.hpp's comb_geometry).
  if (ImGui::SliderFloat("size (1 = fits)", &scale, 0.1f, 4.0f, "%.2f", ImGuiSliderFlags_Logarithmic)) e.comb_scale = scale;
  ImGui::SetNextItemWidth(80);
  ImGui::SliderInt("teeth/segment", &e.comb_density, 4, 96);
  ImGui::SameLine();
  ImGui::Checkbox("outline", &e.comb_outline);
  std::string group = e.point_name(d.selected);
  for (int g : d.group) group += " + " + e.point_name(g);
  ImGui::Text("moving: %s  (shift-click: group)", group.c_str());
  typed_fields(e, info);
  // The selected point's weight (shift+wheel over a point scales it); a
  // polynomial spline shows weights 1 and becomes rational when one changes.
  if (!d.kcurve) {
    double weight = d.spline.weight(d.selected);
    const double lo = -Editor::kMaxWeight, hi = Editor::kMaxWeight;
    const std::string label =
        "weight of " + e.point_name(d.selected) + (d.spline.is_rational() ? "" : " (polynomial: all 1)");
    ImGui::SetNextItemWidth(120);
    // Any sign (ctrl+click types a value); the step follows the weight's size.
    const float speed = static_cast<float>(0.005 * std::max(std::abs(weight), 0.01));
    if (ImGui::DragScalar(label.c_str(), ImGuiDataType_Double, &weight, speed, &lo, &hi, "%.5g"))
      act(e, [&] { e.set_weight(d.selected, weight); });
    ImGui::Checkbox("region of this weight", &e.show_weight_region);
    weight_strip(e);
  }
  kcurve_controls(e);
}

/// Buttons for the knot operations (engine.hpp's knot_operation): a refusal
/// lands in the status line.
void knot_operations(Editor& e) {
  static double u = 0, tolerance = 0;  // what the fields hold between frames
  const BSpline& s = e.doc().spline;
  if (!(u > s.domain_begin() && u < s.domain_end())) u = 0.5 * (s.domain_begin() + s.domain_end());
  ImGui::SetNextItemWidth(90);
  ImGui::InputDouble("u", &u, 0, 0, "%.4g");
  ImGui::SameLine();
  if (ImGui::Button("insert")) e.knot_operation("insert", u, 1);
  ImGui::SameLine();
  if (ImGui::Button("remove")) e.knot_operation("remove", u, tolerance);
  ImGui::SetNextItemWidth(90);
  ImGui::InputDouble("tolerance (0: 1e-9 of the size)", &tolerance, 0, 0, "%.3g");
  if (ImGui::Button("elevate degree")) e.knot_operation("elevate", 0, 0);
  ImGui::SameLine();
  if (ImGui::Button("clamp")) e.knot_operation("clamp", 0, 0);
  ImGui::SameLine();
  if (ImGui::Button("uniform")) e.knot_operation("uniform", 0, 0);
}

void knot_ruler(Editor& e, KnotRulerGeometry* geometry) {
  const BSpline& s = e.doc().spline;
  const std::vector<double>& u = s.knots();
  const double lo = u.front(), hi = u.back();
  if (!(hi > lo)) return;
  ImGui::TextUnformatted("knots (drag to move)");
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float width = ImGui::GetContentRegionAvail().x - 12, height = 34;
  const auto x_of = [&](double v) { return origin.x + 6 + static_cast<float>((v - lo) / (hi - lo)) * width; };
  if (geometry != nullptr) *geometry = {origin.x + 6, width, lo, hi, {}, true};
  dl->AddLine({origin.x + 6, origin.y + 12}, {origin.x + 6 + width, origin.y + 12}, IM_COL32(200, 200, 200, 255), 2);
  dl->AddRectFilled({x_of(s.domain_begin()), origin.y + 9}, {x_of(s.domain_end()), origin.y + 15},
                    IM_COL32(120, 170, 255, 255));
  for (std::size_t i = 0; i < u.size(); ++i) {
    int stack = 0;  // equal knots stack downwards
    for (std::size_t j = 0; j < i; ++j) stack += u[j] == u[i] ? 1 : 0;
    const float x = x_of(u[i]), y = origin.y + 18 + 5.0f * stack;
    if (geometry != nullptr) geometry->handles.push_back({x, y});
    ImGui::SetCursorScreenPos({x - 5, y - 5});
    ImGui::PushID(static_cast<int>(i));
    ImGui::InvisibleButton("knot", {10, 10});
    const bool active = ImGui::IsItemActive();
    if (active && ImGui::IsMouseDragging(ImGuiMouseButton_Left, 0)) {
      const double lo_i = i > 0 ? u[i - 1] : lo - (hi - lo), hi_i = i + 1 < u.size() ? u[i + 1] : hi + (hi - lo);
      const double want = lo + (ImGui::GetIO().MousePos.x - origin.x - 6) / width * (hi - lo);
      act(e, [&] { e.move_knot(static_cast<int>(i), std::clamp(want, lo_i, hi_i)); });
    }
    ImGui::PopID();
    dl->AddTriangleFilled({x, y - 5}, {x - 5, y + 4}, {x + 5, y + 4},
                          active ? IM_COL32(230, 30, 30, 255) : IM_COL32(40, 40, 40, 255));
  }
  ImGui::SetCursorScreenPos({origin.x, origin.y + height + 10});
  std::string text;
  for (double k : u) {
    if (!text.empty()) text += ' ';  // no "literal" + string: GCC 12 warns falsely (-Wrestrict)
    text += std::to_string(k).substr(0, 5);
  }
  ImGui::TextWrapped("[%s]", text.c_str());
  knot_operations(e);
}

/// Segment verdicts and each segment's certified curvature extrema (the
/// report's, with their parameter and kappa; those on a joint listed with the
/// segment the joint starts).
void verdicts_table(Editor& e) {
  const SplineAnalysis& a = e.analysis();
  const CurvatureEvents& ev = e.events();
  ImGui::Text("CMRWI: %s   CMR: %s", to_string(a.cmrwi), to_string(a.cmr));
  if (a.split) ImGui::Text("split at joint %d: %s", *e.doc().split, to_string(*a.split));
  if (ImGui::BeginTable("segments", 4, ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit)) {
    ImGui::TableSetupColumn("seg");
    ImGui::TableSetupColumn("u");
    ImGui::TableSetupColumn("curvature");
    ImGui::TableSetupColumn("extrema: kappa @ u");
    ImGui::TableHeadersRow();
    static const char* kinds[] = {"sharp", "flat", "infl"};
    for (std::size_t i = 0; i < a.segments.size(); ++i) {
      const Segment& s = e.doc().spline.segments()[i];
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::Text("%zu", i);
      ImGui::TableNextColumn();
      ImGui::Text("%.3g..%.3g", s.a, s.b);
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(a.shapes[i].pole ? "pole (W = 0)" : to_string(a.segments[i].monotonicity.curvature));
      if (a.segments[i].inflection.inflection != Inflection{}) {
        ImGui::SameLine(0, 0);
        ImGui::Text(", infl. %s", to_string(a.segments[i].inflection.inflection));
      }
      ImGui::TableNextColumn();
      std::string text;
      for (const CurvatureEvents::Extremum& x : ev.extrema) {
        if (x.segment != static_cast<int>(i) && x.joint != static_cast<int>(i)) continue;
        char buf[96];
        std::snprintf(buf, sizeof buf, "%s%s %.3g @%.4g", text.empty() ? "" : "\n", kinds[std::clamp(x.kind, 0, 2)],
                      x.kappa, x.t);
        text += buf;
      }
      ImGui::TextUnformatted(text.empty() ? "none" : text.c_str());
    }
    ImGui::EndTable();
  }
}

void file_buttons(Editor& e, const UiInfo& info) {
  if (ImGui::Button("undo")) e.undo();
  ImGui::SameLine();
  if (ImGui::Button("redo")) e.redo();
  ImGui::SameLine();
  if (ImGui::Button("save")) act(e, [&] { e.save(e.path()); });
  ImGui::SameLine();
  if (ImGui::Button("fit")) e.fit_view();
  ImGui::SameLine();
  if (ImGui::Button("fit region")) act(e, [&] { e.fit_region(); });
  // design/fix: the nearest certified fix of the view's requirement (x),
  // the selected point into its region (s); animated, one undo step each.
  // (In the rows that were there: the panel keeps its height.)
  ImGui::SameLine();
  if (ImGui::Button("fix (x)")) e.fix_curve();
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("the nearest certified fix of %s (the points cmr fix chooses)",
                      to_string(e.fix_requirement()).c_str());
  if (!e.curves.empty() && !e.curves[e.active_curve].font_point.empty()) {  // a font's glyph
    ImGui::SameLine();
    if (ImGui::Button("fix on grid")) act(e, [&] { e.fix_on_grid(); });
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("one fix for %s on the font's grid, as cmr fix FONT.ufo --glyph NAME --require finds it "
                        "(lines and smooth nodes kept, every gate re-judged)",
                        e.grid_fix_gates.c_str());
    // The gates it asks for: the type gates a fix can move points for.
    static const char* const kGateChoices[] = {"curvature-extrema-at-nodes", "g2-at-smooth-nodes",
                                               "curvature-extrema-at-nodes,g2-at-smooth-nodes"};
    int choice = -1;
    for (int i = 0; i < 3; ++i)
      if (e.grid_fix_gates == kGateChoices[i]) choice = i;
    ImGui::SameLine();
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 9);
    if (ImGui::BeginCombo("##gridgates", choice == 2 ? "both gates" : e.grid_fix_gates.c_str())) {
      for (int i = 0; i < 3; ++i)
        if (ImGui::Selectable(i == 2 ? "both gates" : kGateChoices[i], choice == i)) e.grid_fix_gates = kGateChoices[i];
      ImGui::EndCombo();
    }
  }
  if (ImGui::Button("export PNG") && info.export_png != nullptr) *info.export_png = true;
  ImGui::SameLine();
  if (ImGui::Button("export region")) {
    std::filesystem::path p = e.path();
    p.replace_extension(".region.pgm");
    act(e, [&] { e.export_region(p); });
  }
  ImGui::SameLine();
  if (ImGui::Button("snap (s)")) e.snap_selected();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("snap P%d into its region: the nearest certified position", e.doc().selected);
}

/// A glyph's contours or an SVG's paths: which one is edited; a font's
/// other glyphs by character.
void curve_picker(Editor& e) {
  if (e.curves.size() > 1) {
    const std::string current = e.curves[e.active_curve].name;
    ImGui::SetNextItemWidth(180);
    if (ImGui::BeginCombo("edited curve", current.c_str())) {
      for (int k = 0; k < static_cast<int>(e.curves.size()); ++k)
        if (ImGui::Selectable(e.curves[k].name.c_str(), k == e.active_curve)) act(e, [&] { e.switch_curve(k); });
      ImGui::EndCombo();
    }
  }
  if (!e.font_path.empty()) {
    static char glyph[16] = "";
    ImGui::SetNextItemWidth(60);
    const bool enter = ImGui::InputText("##glyph", glyph, sizeof glyph, ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    if ((ImGui::Button("open glyph") || enter) && glyph[0] != 0) act(e, [&] { e.open_glyph(glyph); });
  }
  if (e.curves.size() > 1) {
    ImGui::SameLine();
    if (ImGui::Button("save all")) act(e, [&] { e.save_all(); });
  }
}

void legend_contents(Editor& e);

void side_panel(Editor& e, const UiInfo& info) {
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos({io.DisplaySize.x - kPanelWidth, 0});
  ImGui::SetNextWindowSize({kPanelWidth, io.DisplaySize.y});
  // The scrollbar always there: the content's width (the knot ruler's scale)
  // does not change when a long status line makes the panel overflow.
  ImGui::Begin("cmr edit", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_AlwaysVerticalScrollbar);
  ImGui::TextWrapped("%s", e.path().filename().string().c_str());
  curve_picker(e);
  // Docked, the legend is a section of this panel and never covers the curve.
  if (e.show_legend && e.legend_docked && ImGui::CollapsingHeader("legend", ImGuiTreeNodeFlags_DefaultOpen))
    legend_contents(e);
  // How the region reaches the window, in full on hover (one line here).
  ImGui::Text("frame %.1f ms; region path (hover)", info.frame_ms);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", info.region_path.c_str());
  ImGui::Separator();
  controls(e, info);
  ImGui::Separator();
  knot_ruler(e, info.ruler);
  ImGui::Separator();
  verdicts_table(e);
  ImGui::Separator();
  file_buttons(e, info);
  if (!e.message.empty()) ImGui::TextWrapped("%s", e.message.c_str());
  ImGui::End();
}

/// About n round tick values over [lo, hi] (1, 2, 5 times a power of ten).
std::vector<double> nice_ticks(double lo, double hi, int n) {
  std::vector<double> out;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return out;
  const double raw = (hi - lo) / n, mag = std::pow(10, std::floor(std::log10(raw)));
  const double step = raw / mag < 1.5 ? mag : raw / mag < 3.5 ? 2 * mag : raw / mag < 7.5 ? 5 * mag : 10 * mag;
  for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) out.push_back(std::abs(v) < 1e-12 * step ? 0 : v);
  return out;
}

std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

/// kappa against the parameter (or |kappa|, or log10 |kappa|): labelled
/// axes with values, the zero line, knots as ticks with their values, the
/// stretches between certified extrema coloured by direction (red
/// increasing, blue decreasing), the extrema marked, and a read-out of u,
/// kappa and the radius under the pointer.
void curvature_plot(Editor& e) {
  const ImGuiIO& io = ImGui::GetIO();
  const BSpline& s = e.doc().spline;
  // Fixed, opaque and not collapsible: the region is not computed beneath it.
  ImGui::SetNextWindowPos({0, io.DisplaySize.y - Editor::kPlotHeight});
  ImGui::SetNextWindowSize({std::max(200.0f, io.DisplaySize.x - kPanelWidth), Editor::kPlotHeight});
  ImGui::Begin("curvature", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::RadioButton("kappa", &e.graph_view, 0);
  ImGui::SameLine();
  ImGui::RadioButton("|kappa|", &e.graph_view, 1);
  ImGui::SameLine();
  ImGui::RadioButton("log10 |kappa|", &e.graph_view, 2);
  ImGui::SameLine();
  ImGui::TextDisabled("   across: u, knots marked with their values; up: %s",
                      e.graph_view == 0 ? "kappa" : e.graph_view == 1 ? "|kappa|" : "|kappa|, log scale");
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const float left = 58, bottom = 24;  // room for the value labels
  const ImVec2 c0 = ImGui::GetCursorScreenPos(), avail = ImGui::GetContentRegionAvail();
  const ImVec2 o{c0.x + left, c0.y + 4};
  const ImVec2 size{std::max(10.0f, avail.x - left - 8), std::max(10.0f, avail.y - bottom - 4)};
  const double a = s.domain_begin(), b = s.domain_end();
  const int view = std::clamp(e.graph_view, 0, 2);
  const auto value = [&](double k) {
    if (view == 0) return k;
    if (view == 1) return std::abs(k);
    return std::abs(k) > 0 ? std::log10(std::abs(k)) : -INFINITY;
  };
  std::vector<double> t(kPlotSamples + 1), k(kPlotSamples + 1), y(kPlotSamples + 1);
  double lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i <= kPlotSamples; ++i) {
    t[i] = a + (b - a) * i / kPlotSamples;
    k[i] = curvature(s, t[i]);
    y[i] = value(k[i]);
    if (std::isfinite(y[i])) lo = std::min(lo, y[i]), hi = std::max(hi, y[i]);
  }
  if (view != 2) lo = std::min(lo, 0.0), hi = std::max(hi, 0.0);  // the zero line is in view
  if (view == 2 && hi - lo > 8) lo = hi - 8;                        // eight decades below the top
  if (!std::isfinite(lo) || !std::isfinite(hi)) lo = 0, hi = 1;
  if (!(hi > lo)) hi = lo + 1;
  const auto px = [&](double tt, double vv) {
    const double yy = std::clamp(vv, lo, hi);
    return ImVec2{o.x + static_cast<float>((tt - a) / (b - a)) * size.x,
                  o.y + static_cast<float>((hi - yy) / (hi - lo)) * size.y};
  };
  const ImU32 axis = IM_COL32(60, 60, 60, 255), grid = IM_COL32(215, 215, 215, 255);
  // y axis: values and grid lines.
  for (double v : nice_ticks(lo, hi, 4)) {
    const float yy = px(a, v).y;
    dl->AddLine({o.x, yy}, {o.x + size.x, yy}, grid);
    const std::string label = short_number(view == 2 ? std::pow(10.0, v) : v);
    const ImVec2 ts = ImGui::CalcTextSize(label.c_str());
    dl->AddText({o.x - ts.x - 4, yy - ts.y / 2}, axis, label.c_str());
  }
  if (view != 2 && lo <= 0 && hi >= 0) {  // the zero line
    const float yy = px(a, 0).y;
    dl->AddLine({o.x, yy}, {o.x + size.x, yy}, IM_COL32(0, 0, 0, 255), 1.5f);
  }
  dl->AddLine({o.x, o.y}, {o.x, o.y + size.y}, axis);
  dl->AddLine({o.x, o.y + size.y}, {o.x + size.x, o.y + size.y}, axis);
  // Knots: ticks with their values under the axis (a value that would
  // overprint the previous one is left out).
  std::set<double> knots(s.knots().begin(), s.knots().end());
  float last_right = -1e9f;
  for (double u : knots) {
    if (u < a || u > b) continue;
    const float x = px(u, lo).x;
    dl->AddLine({x, o.y}, {x, o.y + size.y}, IM_COL32(170, 170, 170, 255));
    dl->AddLine({x, o.y + size.y}, {x, o.y + size.y + 5}, axis, 1.5f);
    const std::string label = short_number(u);
    const ImVec2 ts = ImGui::CalcTextSize(label.c_str());
    if (x - ts.x / 2 > last_right + 4) {
      dl->AddText({x - ts.x / 2, o.y + size.y + 6}, axis, label.c_str());
      last_right = x + ts.x / 2;
    }
  }
  std::vector<double> cuts = e.events().maxima;
  cuts.insert(cuts.end(), e.events().minima.begin(), e.events().minima.end());
  std::sort(cuts.begin(), cuts.end());
  for (int i = 1; i <= kPlotSamples; ++i) {
    // A stretch between consecutive extrema is monotone: its direction is
    // the sign of kappa's change across it.
    const double mid = 0.5 * (t[i - 1] + t[i]);
    const auto hi_it = std::upper_bound(cuts.begin(), cuts.end(), mid);
    const double s0 = hi_it == cuts.begin() ? a : *(hi_it - 1), s1 = hi_it == cuts.end() ? b : *hi_it;
    const bool increasing = curvature(s, s1 - 1e-9 * (b - a)) >= curvature(s, s0 + 1e-9 * (b - a));
    if (!std::isfinite(y[i - 1]) || !std::isfinite(y[i])) continue;
    dl->AddLine(px(t[i - 1], y[i - 1]), px(t[i], y[i]), increasing ? kIncreasingColour : kDecreasingColour, 2);
  }
  for (const CurvatureEvents::Extremum& x : e.events().extrema) {
    const double v = value(x.kappa);
    if (!std::isfinite(v)) continue;
    dl->AddCircleFilled(px(x.t, v), 4, x.kind == 0 ? kMaximumColour : x.kind == 1 ? kMinimumColour : kInflectionColour);
  }
  // The pointer's read-out.
  const ImVec2 m = io.MousePos;
  if (m.x >= o.x && m.x <= o.x + size.x && m.y >= o.y && m.y <= o.y + size.y && ImGui::IsWindowHovered()) {
    const double u = a + (m.x - o.x) / size.x * (b - a);
    const double kk = curvature(s, u);
    dl->AddLine({m.x, o.y}, {m.x, o.y + size.y}, IM_COL32(0, 0, 0, 120));
    if (std::isfinite(value(kk))) dl->AddCircle(px(u, value(kk)), 4, IM_COL32(0, 0, 0, 255));
    ImGui::SetTooltip("u = %.6g\nkappa = %.6g\nradius = %.6g", u, kk, kk != 0 ? 1 / std::abs(kk) : INFINITY);
  }
  ImGui::End();
}

/// The legend of what the canvas shows (designer.hpp's region_legend), at
/// its top left; with every point overlapped, a switch per point.
void legend_contents(Editor& e) {
  const Legend l = region_legend(e);
  ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + 290);
  ImGui::TextWrapped("%s", l.title.c_str());
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const float h = ImGui::GetTextLineHeight();
  for (const LegendLine& x : l.lines) {
    if (x.same_row) ImGui::SameLine(0, 14);
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const ImVec2 a{p.x, p.y + 1}, b{p.x + 18, p.y + h - 1};
    const ImVec2 mid{p.x + 9, p.y + h / 2};
    const ImU32 col = colour_u32(x.colour);
    switch (x.kind) {
      case LegendLine::Kind::swatch:
        dl->AddRectFilled(a, b, col);
        dl->AddRect(a, b, IM_COL32(0, 0, 0, 255));
        break;
      case LegendLine::Kind::gradient:
        dl->AddRectFilledMultiColor(a, b, col, colour_u32(x.colour_to), colour_u32(x.colour_to), col);
        dl->AddRect(a, b, IM_COL32(0, 0, 0, 255));
        break;
      case LegendLine::Kind::outline: dl->AddRect(a, b, col, 0, 0, 2.5f); break;
      case LegendLine::Kind::dot: dl->AddCircleFilled(mid, 5, col); break;
      case LegendLine::Kind::square: dl->AddRectFilled({mid.x - 5, mid.y - 5}, {mid.x + 5, mid.y + 5}, col); break;
      case LegendLine::Kind::diamond:
        dl->AddQuadFilled({mid.x, mid.y - 6}, {mid.x + 6, mid.y}, {mid.x, mid.y + 6}, {mid.x - 6, mid.y}, col);
        break;
      case LegendLine::Kind::line: dl->AddLine({a.x, mid.y}, {b.x, mid.y}, col, 2); break;
      case LegendLine::Kind::text: break;
    }
    ImGui::Dummy({22, h});
    ImGui::SameLine();
    // The marks share rows: never wrapped (the region entries are).
    const bool mark = x.kind != LegendLine::Kind::swatch && x.kind != LegendLine::Kind::gradient &&
                      x.kind != LegendLine::Kind::outline;
    if (mark) ImGui::PushTextWrapPos(-1.0f);
    ImGui::TextUnformatted(x.text.c_str());
    if (mark) ImGui::PopTextWrapPos();
  }
  ImGui::PopTextWrapPos();
}

void legend_window(Editor& e) {
  ImGui::SetNextWindowPos({6, 6}, ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.88f);
  // The pointer passes through it: points and regions beneath stay in reach.
  ImGui::Begin("legend", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoInputs | ImGuiWindowFlags_NoTitleBar);
  legend_contents(e);
  ImGui::End();
}

/// Under the pointer on the canvas: the curve's parameter, curvature and
/// radius; a point's name and coordinates; the points whose regions hold the
/// pixel (every point overlapped).
void canvas_readout(Editor& e) {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantCaptureMouse || e.dragging() >= 0) return;
  const ImVec2 m = io.MousePos;
  const auto [cw, ch] = e.canvas();
  if (!(m.x >= 0 && m.y >= 0 && m.x < cw && m.y < ch)) return;
  const Document& d = e.doc();
  std::string text = e.point_hover(m.x, m.y);  // the full name ("O/c0/p3") and coordinates
  if (text.empty())
    if (const auto c = pick_curve(d.spline, e.viewport(), m.x, m.y, 8)) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "u = %.6g\nkappa = %.6g\nradius = %.6g", c->t, c->kappa,
                    c->kappa != 0 ? 1 / std::abs(c->kappa) : INFINITY);
      text = buf;
      ImGui::GetForegroundDrawList()->AddCircle(screen(e, c->point), 5, IM_COL32(0, 0, 0, 255), 0, 2);
    }
  if (d.all_points) {
    const std::vector<const RegionResult*>& layers = e.region();
    const std::vector<int> points = e.layer_points();
    const int c = e.region_coarse();
    std::string owners;
    for (std::size_t l = 0; l < layers.size() && l < points.size(); ++l) {
      const RegionResult& r = *layers[l];
      const int i = static_cast<int>(m.x) / c, j = static_cast<int>(m.y) / c;
      if (i < r.width && j < r.height && r.in_region(static_cast<std::size_t>(j) * r.width + i))
        owners += (owners.empty() ? "" : ", ") + e.point_name(points[l]);
    }
    if (!owners.empty()) text += (text.empty() ? "" : "\n") + ("in the region of " + owners);
  }
  if (!text.empty()) ImGui::SetTooltip("%s", text.c_str());
}

}  // namespace

void build_ui(Editor& e, const UiInfo& info) {
  if (e.show_overlay) {
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    const Document& d = e.doc();
    // While too few κ points are clicked there is no curve yet to draw.
    if (!d.kcurve || static_cast<int>(d.kcurve->points.size()) >= kKCurveMinPoints) {
      draw_outlines(e, dl);
      draw_curve(e, dl);
      if (e.show_comb) draw_comb(e, dl);
      draw_marks(e, dl);
      draw_points(e, dl);
    }
    draw_kcurve(e, dl);
  }
  if (info.ruler != nullptr) info.ruler->shown = false;
  if (!e.show_ui) return;
  side_panel(e, info);
  curvature_plot(e);
  if (e.show_legend && !e.legend_docked) legend_window(e);
  canvas_readout(e);
}

}  // namespace cmr::edit
