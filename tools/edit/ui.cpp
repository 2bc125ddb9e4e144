#include "tools/edit/ui.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <set>

#include "bezierize/kcurve.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"

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
    e.message = err.what();
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

void draw_comb(Editor& e, ImDrawList* dl) {
  const BSpline& s = e.doc().spline;
  double kmax = 0;
  std::vector<std::pair<Vec2, Vec2>> teeth;  // point, normal * kappa
  const CurveSampler comb_sampler(s);          // none near a pole
  for (const Segment& seg : s.segments()) {
    for (int i = 0; i <= kCombTeethPerSegment; ++i) {
      const double t = seg.a + (seg.b - seg.a) * i / kCombTeethPerSegment;
      const CurvatureSample c = curvature_at(s, t);
      const Vec2 d = derivative(s, t, 1);
      const double len = std::hypot(d.x, d.y);
      if (!(len > 0) || !std::isfinite(c.kappa) || !comb_sampler.inside(c.point)) continue;
      teeth.push_back({c.point, Vec2{-d.y, d.x} * (c.kappa / len)});
      kmax = std::max(kmax, std::abs(c.kappa));
    }
  }
  if (!(kmax > 0)) return;
  const View& v = e.viewport().view;
  const double unit = e.comb_scale * (v.x1 - v.x0) / 8 / kmax;
  ImVec2 prev{};
  for (std::size_t i = 0; i < teeth.size(); ++i) {
    // Teeth point away from the centre of curvature, as combs usually do.
    const ImVec2 a = screen(e, teeth[i].first), b = screen(e, teeth[i].first - teeth[i].second * unit);
    dl->AddLine(a, b, kCombColour);
    if (i > 0) dl->AddLine(prev, b, kCombColour);
    prev = b;
  }
  const CurvatureEvents& ev = e.events();
  for (double t : ev.maxima) dl->AddCircleFilled(screen(e, evaluate(s, t)), 6, kMaximumColour);
  for (double t : ev.minima) dl->AddCircleFilled(screen(e, evaluate(s, t)), 6, kMinimumColour);
  for (double t : ev.inflections) {
    const ImVec2 p = screen(e, evaluate(s, t));
    dl->AddRectFilled({p.x - 5, p.y - 5}, {p.x + 5, p.y + 5}, kInflectionColour);
  }
}

void draw_points(Editor& e, ImDrawList* dl) {
  const Document& d = e.doc();
  const std::vector<Vec2>& pts = d.spline.points();
  for (std::size_t i = 1; i < pts.size(); ++i) dl->AddLine(screen(e, pts[i - 1]), screen(e, pts[i]), kPolygonColour);
  for (int i = 0; i < d.spline.point_count(); ++i) {
    const ImVec2 p = screen(e, pts[i]);
    const bool grouped = std::find(d.group.begin(), d.group.end(), i) != d.group.end();
    const ImU32 fill = i == d.selected ? IM_COL32(230, 30, 30, 255)
                                       : (grouped ? IM_COL32(240, 150, 0, 255) : IM_COL32(255, 255, 255, 255));
    dl->AddCircleFilled(p, 5.5f, fill);
    dl->AddCircle(p, 5.5f, IM_COL32(0, 0, 0, 255), 0, 1.5f);
    std::string name = "P";  // built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + string
    name += std::to_string(i);
    dl->AddText({p.x + 7, p.y - 18}, IM_COL32(0, 0, 0, 255), name.c_str());
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

void controls(Editor& e) {
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
  if (ImGui::Checkbox("Bezier chain (G1 handles)", &chain)) act(e, [&] { e.set_chain(chain); });
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
  ImGui::Checkbox("curvature comb", &e.show_comb);
  ImGui::SameLine();
  float scale = static_cast<float>(e.comb_scale);
  ImGui::SetNextItemWidth(110);
  if (ImGui::SliderFloat("scale", &scale, 0.1f, 5.0f, "%.2f", ImGuiSliderFlags_Logarithmic)) e.comb_scale = scale;
  std::string group = "P" + std::to_string(d.selected);
  for (int g : d.group) group += " + P" + std::to_string(g);
  ImGui::Text("moving: %s  (shift-click: group)", group.c_str());
  // The selected point's weight (shift+wheel over a point scales it); a
  // polynomial spline shows weights 1 and becomes rational when one changes.
  if (!d.kcurve) {
    double weight = d.spline.weight(d.selected);
    const double lo = -Editor::kMaxWeight, hi = Editor::kMaxWeight;
    const std::string label =
        "weight of P" + std::to_string(d.selected) + (d.spline.is_rational() ? "" : " (polynomial: all 1)");
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

void verdicts_table(Editor& e) {
  const SplineAnalysis& a = e.analysis();
  ImGui::Text("CMRWI: %s   CMR: %s", to_string(a.cmrwi), to_string(a.cmr));
  if (a.split) ImGui::Text("split at joint %d: %s", *e.doc().split, to_string(*a.split));
  if (ImGui::BeginTable("segments", 4, ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit)) {
    ImGui::TableSetupColumn("seg");
    ImGui::TableSetupColumn("interval");
    ImGui::TableSetupColumn("curvature");
    ImGui::TableSetupColumn("inflection");
    ImGui::TableHeadersRow();
    for (std::size_t i = 0; i < a.segments.size(); ++i) {
      const Segment& s = e.doc().spline.segments()[i];
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::Text("%zu", i);
      ImGui::TableNextColumn();
      ImGui::Text("[%.3g, %.3g]", s.a, s.b);
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(a.shapes[i].pole ? "pole (W = 0)" : to_string(a.segments[i].monotonicity.curvature));
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(to_string(a.segments[i].inflection.inflection));
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
  // bezierize/fix: the nearest certified fix of the view's requirement (x),
  // the selected point into its region (s); animated, one undo step each.
  // (In the rows that were there: the panel keeps its height.)
  ImGui::SameLine();
  if (ImGui::Button("fix (x)")) e.fix_curve();
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("the nearest certified fix of %s (the points cmr fix chooses)",
                      to_string(e.fix_requirement()).c_str());
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

void side_panel(Editor& e, const UiInfo& info) {
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos({io.DisplaySize.x - kPanelWidth, 0});
  ImGui::SetNextWindowSize({kPanelWidth, io.DisplaySize.y});
  ImGui::Begin("cmr edit", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::TextWrapped("%s", e.path().filename().string().c_str());
  ImGui::TextWrapped("%s", info.region_path.c_str());
  ImGui::Text("frame %.1f ms", info.frame_ms);
  ImGui::Separator();
  controls(e);
  ImGui::Separator();
  knot_ruler(e, info.ruler);
  ImGui::Separator();
  verdicts_table(e);
  ImGui::Separator();
  file_buttons(e, info);
  if (!e.message.empty()) ImGui::TextWrapped("%s", e.message.c_str());
  ImGui::End();
}

/// kappa against the parameter: the stretches between certified extrema
/// coloured by direction (red increasing, blue decreasing), knots as ticks.
void curvature_plot(Editor& e) {
  const ImGuiIO& io = ImGui::GetIO();
  const BSpline& s = e.doc().spline;
  // Fixed, opaque and not collapsible: the region is not computed beneath it.
  ImGui::SetNextWindowPos({0, io.DisplaySize.y - Editor::kPlotHeight});
  ImGui::SetNextWindowSize({std::max(200.0f, io.DisplaySize.x - kPanelWidth), Editor::kPlotHeight});
  ImGui::Begin("curvature", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 o = ImGui::GetCursorScreenPos(), size = ImGui::GetContentRegionAvail();
  const double a = s.domain_begin(), b = s.domain_end();
  std::vector<double> t(kPlotSamples + 1), k(kPlotSamples + 1);
  double kmin = 0, kmax = 0;
  for (int i = 0; i <= kPlotSamples; ++i) {
    t[i] = a + (b - a) * i / kPlotSamples;
    k[i] = curvature(s, t[i]);
    if (std::isfinite(k[i])) kmin = std::min(kmin, k[i]), kmax = std::max(kmax, k[i]);
  }
  if (!(kmax > kmin)) kmax = kmin + 1;
  const auto px = [&](double tt, double kk) {
    return ImVec2{o.x + static_cast<float>((tt - a) / (b - a)) * size.x,
                  o.y + static_cast<float>((kmax - kk) / (kmax - kmin)) * (size.y - 4)};
  };
  dl->AddLine(px(a, 0), px(b, 0), IM_COL32(150, 150, 150, 255));
  std::set<double> knots(s.knots().begin(), s.knots().end());
  for (double u : knots) {
    if (u < a || u > b) continue;
    dl->AddLine({px(u, 0).x, o.y}, {px(u, 0).x, o.y + size.y}, IM_COL32(110, 110, 110, 255));
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
    if (!std::isfinite(k[i - 1]) || !std::isfinite(k[i])) continue;
    dl->AddLine(px(t[i - 1], k[i - 1]), px(t[i], k[i]), increasing ? kIncreasingColour : kDecreasingColour, 2);
  }
  for (double u : e.events().maxima) dl->AddCircleFilled(px(u, curvature(s, u)), 4, kMaximumColour);
  for (double u : e.events().minima) dl->AddCircleFilled(px(u, curvature(s, u)), 4, kMinimumColour);
  ImGui::End();
}

}  // namespace

void build_ui(Editor& e, const UiInfo& info) {
  if (e.show_overlay) {
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    const Document& d = e.doc();
    // While too few κ points are clicked there is no curve yet to draw.
    if (!d.kcurve || static_cast<int>(d.kcurve->points.size()) >= kKCurveMinPoints) {
      draw_curve(e, dl);
      if (e.show_comb) draw_comb(e, dl);
      draw_points(e, dl);
    }
    draw_kcurve(e, dl);
  }
  if (info.ruler != nullptr) info.ruler->shown = false;
  if (!e.show_ui) return;
  side_panel(e, info);
  curvature_plot(e);
}

}  // namespace cmr::edit
