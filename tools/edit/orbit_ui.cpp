// The orbit view's ImGui layer (tools/edit/orbit.hpp): the canvas (plane,
// region, control polygon, comb, torsion-coloured curve, points, axes), the
// legend and the side panel. Buttons call the same OrbitView actions the
// script does.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "draw/draw.hpp"
#include "tools/edit/orbit.hpp"

namespace cmr::edit {
namespace {

constexpr int kPanel = kOrbitPanel;

ImU32 rgb(double r, double g, double b, double a = 1) {
  const auto c = [](double x) { return static_cast<int>(std::lround(255 * std::clamp(x, 0.0, 1.0))); };
  return IM_COL32(c(r), c(g), c(b), c(a));
}
ImU32 rgb(const draw::Rgb& c, double a = 1) { return rgb(c.r, c.g, c.b, a); }

/// Torsion colour: dark grey at tau = 0, towards green (tau > 0) or purple
/// (tau < 0) with |tau| / max |tau|.
draw::Rgb torsion_colour(double tau, double tau_max) {
  const draw::Rgb base{0.3, 0.3, 0.3}, pos{0.0, 0.62, 0.25}, neg{0.55, 0.1, 0.75};
  const double m = tau_max > 0 ? std::clamp(std::abs(tau) / tau_max, 0.0, 1.0) : 0.0;
  const draw::Rgb& h = tau >= 0 ? pos : neg;
  return {base.r + (h.r - base.r) * m, base.g + (h.g - base.g) * m, base.b + (h.b - base.b) * m};
}

/// max |tau| worth colouring: below 1e-9 of the largest kappa (or 1e-12) the curve is planar.
double colour_tau_max(const OrbitView& v) {
  return v.tau_max() > std::max(1e-12, 1e-9 * v.kappa_max()) ? v.tau_max() : 0.0;
}

const draw::Rgb kPolygon{0.55, 0.55, 0.55}, kComb{0.45, 0.62, 0.85}, kPlane{0.35, 0.35, 0.45};
const draw::Rgb kSharpest{1.0, 0.55, 0.0}, kFlattest{0.0, 0.75, 0.85};

ImVec2 iv(Vec2 p) { return {static_cast<float>(p.x), static_cast<float>(p.y)}; }

void draw_canvas(OrbitView& v, const OrbitRegion* region) {
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  const OrbitProjection p = v.projection();
  const auto line = [&](const Vec3& a, const Vec3& b, ImU32 col, float w) {
    Vec2 s, t;
    if (p.to_screen(a, s) && p.to_screen(b, t)) dl->AddLine(iv(s), iv(t), col, w);
  };
  const auto quad = [&](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, ImU32 col) {
    Vec2 s[4];
    if (p.to_screen(a, s[0]) && p.to_screen(b, s[1]) && p.to_screen(c, s[2]) && p.to_screen(d, s[3]))
      dl->AddQuadFilled(iv(s[0]), iv(s[1]), iv(s[2]), iv(s[3]), col);
  };
  // Depth against the one surface, the plane: what lies behind it (seen from
  // the eye) is drawn first, then the plane and the region, then the rest;
  // lines that cross the plane are cut where they cross it.
  const SpaceSpline& s = v.spline();
  const int m = s.unique_point_count();
  Vec3 normal{0.0}, origin{0.0};
  double eps = 0;
  if (region != nullptr) {
    origin = region->plane.origin;
    normal = glm::normalize(glm::cross(region->plane.u, region->plane.v));
    if (glm::dot(p.eye - origin, normal) < 0) normal = -normal;  // the eye's side is the front
    Vec3 lo{1e300}, hi{-1e300};
    for (const Vec3& q : s.points()) lo = glm::min(lo, q), hi = glm::max(hi, q);
    eps = 1e-9 * glm::length(hi - lo);
  }
  const auto side = [&](const Vec3& q) { return region != nullptr ? glm::dot(q - origin, normal) : 1.0; };
  const auto in_pass = [&](const Vec3& q, bool front) { return (side(q) >= -eps) == front; };
  const auto cut = [&](const Vec3& a, const Vec3& b, ImU32 col, float w, bool front) {
    const double da = side(a), db = side(b);
    if ((da >= -eps) == (db >= -eps)) {
      if ((da >= -eps) == front) line(a, b, col, w);
      return;
    }
    const Vec3 c = a + (da / (da - db)) * (b - a);
    if ((da >= -eps) == front) line(a, c, col, w);
    else line(c, b, col, w);
  };
  const auto scene = [&](bool front) {
    // Control polygon.
    for (int k = 0; k + 1 < s.point_count(); ++k) cut(s.points()[k], s.points()[k + 1], rgb(kPolygon), 1.5f, front);
    // Comb: teeth along the principal normal, tips joined.
    const auto& samples = v.samples();
    if (v.comb) {
      for (std::size_t i = 0; i < samples.size(); ++i) {
        cut(samples[i].p, samples[i].comb, rgb(kComb, 0.8), 1.0f, front);
        if (i > 0) cut(samples[i - 1].comb, samples[i].comb, rgb(kComb), 1.0f, front);
      }
    }
    // The curve, coloured by its torsion.
    const double tm = colour_tau_max(v);
    for (std::size_t i = 1; i < samples.size(); ++i)
      cut(samples[i - 1].p, samples[i].p, rgb(torsion_colour(0.5 * (samples[i - 1].tau + samples[i].tau), tm)), 3.0f, front);
    // Certified curvature extrema: sharpest (maxima of |kappa|) orange, flattest cyan.
    for (const OrbitView::Extremum& e : v.extrema()) {
      Vec2 q;
      if (p.to_screen(e.p, q)) if (in_pass(e.p, front)) dl->AddCircleFilled(iv(q), 4.0f, rgb(e.maximum ? kSharpest : kFlattest));
    }
    // Points and names.
    for (int k = 0; k < m; ++k) {
      Vec2 q;
      if (!p.to_screen(s.points()[k], q) || !in_pass(s.points()[k], front)) continue;
      const bool sel = k == v.selected();
      dl->AddCircleFilled(iv(q), sel ? 6.0f : 4.5f, sel ? IM_COL32(20, 20, 20, 255) : IM_COL32(90, 90, 90, 255));
      if (sel) dl->AddCircle(iv(q), 10.0f, IM_COL32(20, 20, 20, 255), 0, 1.5f);
      char name[16];
      std::snprintf(name, sizeof name, "P%d", k);
      dl->AddText({static_cast<float>(q.x) + 8, static_cast<float>(q.y) - 18}, IM_COL32(30, 30, 30, 255), name);
    }
  };
  if (region != nullptr) scene(false);
  // The plane: the region's view as a translucent quad with a grid.
  if (region != nullptr) {
    const View& w = region->view;
    const auto at = [&](double a, double b) { return region->plane.origin + a * region->plane.u + b * region->plane.v; };
    quad(at(w.x0, w.y0), at(w.x1, w.y0), at(w.x1, w.y1), at(w.x0, w.y1), rgb(kPlane, 0.10));
    // Each row's runs of one monotone label, one quad each; cells inside the
    // detail's box are drawn from the detail.
    const auto runs = [&](const View& vw, int width, int height, const std::vector<Direction>& labels,
                          const View* skip) {
      const double da = (vw.x1 - vw.x0) / width, db = (vw.y1 - vw.y0) / height;
      for (int j = 0; j < height; ++j) {
        const double b1 = vw.y1 - db * j, b0 = vw.y1 - db * (j + 1);
        const bool row_in = skip != nullptr && b0 >= skip->y0 - 0.25 * db && b1 <= skip->y1 + 0.25 * db;
        for (int i = 0; i < width;) {
          const auto label = [&](int x) {
            const double c = vw.x0 + da * (x + 0.5);
            if (row_in && c > skip->x0 && c < skip->x1) return Direction::none;
            return labels[static_cast<std::size_t>(j) * width + x];
          };
          const Direction l = label(i);
          int e = i + 1;
          while (e < width && label(e) == l) ++e;
          if (l == Direction::increasing || l == Direction::decreasing) {
            const double a0 = vw.x0 + da * i, a1 = vw.x0 + da * e;
            quad(at(a0, b0), at(a1, b0), at(a1, b1), at(a0, b1), rgb(draw::label_colour(static_cast<uint8_t>(l), false)));
          }
          i = e;
        }
      }
    };
    const bool detail = !region->detail.empty();
    runs(w, region->width, region->height, region->labels, detail ? &region->detail_view : nullptr);
    if (detail) runs(region->detail_view, region->detail_width, region->detail_height, region->detail, nullptr);
    const ImU32 grid = rgb(kPlane, 0.35);
    for (int g = 0; g <= 8; ++g) {
      const double a = w.x0 + (w.x1 - w.x0) * g / 8, b = w.y0 + (w.y1 - w.y0) * g / 8;
      line(at(a, w.y0), at(a, w.y1), grid, g % 8 == 0 ? 1.5f : 1.0f);
      line(at(w.x0, b), at(w.x1, b), grid, g % 8 == 0 ? 1.5f : 1.0f);
    }
  }
  scene(true);
  // Axes: x red, y green, z blue, at the canvas's bottom left.
  const Vec2 o{40.0, v.height() - 40.0};
  const char* names[3] = {"x", "y", "z"};
  const ImU32 cols[3] = {IM_COL32(200, 40, 40, 255), IM_COL32(40, 150, 40, 255), IM_COL32(40, 40, 200, 255)};
  for (int a = 0; a < 3; ++a) {
    Vec3 e{0.0};
    e[a] = 1;
    const Vec2 d{25 * glm::dot(e, p.right), -25 * glm::dot(e, p.up)};
    dl->AddLine(iv(o), iv(o + d), cols[a], 2.0f);
    dl->AddText(iv(o + 1.2 * d - Vec2{3, 7}), cols[a], names[a]);
  }
}

std::string verdict_text(Direction d) {
  switch (d) {
    case Direction::increasing: return "increasing";
    case Direction::decreasing: return "decreasing";
    case Direction::none: return "not monotone";
    default: return "undecided";
  }
}

void swatch(const draw::Rgb& c, const char* text, bool outline, bool dot) {
  const ImVec2 at = ImGui::GetCursorScreenPos();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  if (dot) dl->AddCircleFilled({at.x + 7, at.y + 7}, 5, rgb(c));
  else dl->AddRectFilled(at, {at.x + 14, at.y + 14}, rgb(c));
  if (outline) dl->AddRect(at, {at.x + 14, at.y + 14}, IM_COL32(120, 120, 120, 255));
  ImGui::Dummy({18, 14});
  ImGui::SameLine();
  ImGui::TextUnformatted(text);
}

void draw_legend(const OrbitView& v) {
  ImGui::SetNextWindowPos({8, 8}, ImGuiCond_Always);
  ImGui::SetNextWindowSize({260, 0}, ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("legend##orbit", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoInputs |
                   ImGuiWindowFlags_NoFocusOnAppearing);
  for (const std::string& line : orbit_legend(v)) {
    // "kind r,g,b words"
    const auto sp1 = line.find(' '), sp2 = line.find(' ', sp1 + 1);
    const std::string kind = line.substr(0, sp1), words = line.substr(sp2 + 1);
    int r = 0, g = 0, b = 0;
    std::sscanf(line.c_str() + sp1 + 1, "%d,%d,%d", &r, &g, &b);
    if (kind == "title") ImGui::TextWrapped("%s", words.c_str());
    else swatch({r / 255.0, g / 255.0, b / 255.0}, words.c_str(), kind == "swatch", kind == "dot");
  }
  ImGui::End();
}

void draw_panel(OrbitView& v, double frame_ms) {
  ImGui::SetNextWindowPos({static_cast<float>(v.width() - kPanel), 0}, ImGuiCond_Always);
  ImGui::SetNextWindowSize({static_cast<float>(kPanel), static_cast<float>(v.height())}, ImGuiCond_Always);
  ImGui::Begin("space curve##orbit", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize);
  const SpaceSpline& s = v.spline();
  const SpaceAnalysis& a = v.analysis();
  ImGui::TextWrapped("%s: %d points, degree %d, %d segments%s", v.path().filename().c_str(), s.unique_point_count(),
                     s.degree(), s.segment_count(), s.is_rational() ? ", rational" : "");
  ImGui::Text("|kappa|: %s", verdict_text(a.curvature).c_str());
  if (a.torsion) ImGui::Text("torsion: %s", verdict_text(*a.torsion).c_str());
  ImGui::Text("kappa %.4g .. %.4g (sampled)", v.kappa_min(), v.kappa_max());
  ImGui::Text("|tau| <= %.4g (sampled)", v.tau_max());
  if (ImGui::BeginTable("segments##orbit", 4, ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit)) {
    ImGui::TableSetupColumn("seg");
    ImGui::TableSetupColumn("|kappa|");
    ImGui::TableSetupColumn("torsion");
    ImGui::TableSetupColumn("tau sign");
    ImGui::TableHeadersRow();
    for (std::size_t i = 0; i < a.segments.size(); ++i) {
      const SpaceSegmentResult& r = a.segments[i];
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::Text("%zu", i);
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(to_string(r.curvature.curvature));
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(r.torsion ? to_string(r.torsion->curvature) : "-");
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(r.torsion_sign > 0 ? "positive" : r.torsion_sign < 0 ? "negative" : "changes");
    }
    ImGui::EndTable();
  }
  for (std::size_t i = 0; i < a.segments.size(); ++i)  // the certified extrema, as the space report lists them
    for (const OrbitView::Extremum& e : v.extrema())
      if (e.t >= s.segments()[i].a && e.t <= s.segments()[i].b)
        ImGui::Text("seg %zu: %s |kappa| %.4g at u=%.4g", i, e.maximum ? "max" : "min", e.kappa, e.t);
  for (const SpaceJoint& j : a.joints)
    ImGui::Text("joint %d (u=%g): %s, jump %s", j.index, j.knot, j.g2 ? "G2" : j.g1 ? "G1" : "G0", jump_name(j.jump));
  ImGui::Separator();
  const int k = v.selected();
  const Vec3 q = s.points()[k];
  ImGui::Text("P%d (%.5g, %.5g, %.5g)", k, q.x, q.y, q.z);
  ImGui::Text("moves in: %s plane", orbit_plane_name(v.plane_kind()));
  const char* kinds[] = {"region", "screen", "xy", "yz", "zx"};
  int kind = static_cast<int>(v.plane_kind());
  if (ImGui::Combo("plane", &kind, kinds, 5)) v.set_plane_kind(static_cast<OrbitPlane>(kind));
  ImGui::Text("here: %s (certified)", verdict_text(v.label_here()).c_str());
  ImGui::Checkbox("region", &v.show_region);
  ImGui::SameLine();
  ImGui::Checkbox("comb", &v.comb);
  float yaw = static_cast<float>(v.camera.yaw * 180 / M_PI), pitch = static_cast<float>(v.camera.pitch * 180 / M_PI);
  if (ImGui::SliderFloat("yaw", &yaw, -180, 180) | ImGui::SliderFloat("pitch", &pitch, -89, 89)) v.orbit(yaw, pitch);
  if (ImGui::Button("fit")) v.fit();
  ImGui::SameLine();
  if (ImGui::Button("fix (x)")) v.fix();
  ImGui::SameLine();
  if (ImGui::Button("undo")) v.undo();
  ImGui::SameLine();
  if (ImGui::Button("redo")) v.redo();
  ImGui::Separator();
  ImGui::TextWrapped("%s", v.message.c_str());
  ImGui::Text("%.1f ms/frame", frame_ms);
  ImGui::End();
}

}  // namespace

std::vector<std::string> orbit_legend(const OrbitView& v) {
  std::vector<std::string> out;
  const auto add = [&](const char* kind, const draw::Rgb& c, const std::string& words) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%s %d,%d,%d ", kind, static_cast<int>(std::lround(255 * c.r)),
                  static_cast<int>(std::lround(255 * c.g)), static_cast<int>(std::lround(255 * c.b)));
    out.push_back(buf + words);
  };
  std::string title = "Where P";
  title += std::to_string(v.selected());
  title += " may go in its ";
  title += orbit_plane_name(v.plane_kind());
  title += " plane: CMRWI, |kappa| monotone over the whole curve";
  add("title", {0, 0, 0}, title);
  add("swatch", draw::label_colour(1, false), "increasing");
  add("swatch", draw::label_colour(2, false), "decreasing");
  add("swatch", draw::label_colour(0, false), "not monotone (the plane)");
  const double tm = colour_tau_max(v);
  add("line", torsion_colour(1, 1), "curve: torsion > 0 (by |tau|)");
  add("line", torsion_colour(-1, 1), "curve: torsion < 0");
  add("line", torsion_colour(0, 1), tm > 0 ? "curve: torsion near 0" : "curve: planar (torsion 0)");
  if (v.comb) add("line", kComb, "comb (principal normal)");
  bool sharpest = false, flattest = false;
  for (const OrbitView::Extremum& e : v.extrema()) (e.maximum ? sharpest : flattest) = true;
  if (sharpest) add("dot", kSharpest, "sharpest (max |kappa|)");
  if (flattest) add("dot", kFlattest, "flattest (min |kappa|)");
  add("line", kPolygon, "control polygon");
  return out;
}

void build_orbit_ui(OrbitView& v, double frame_ms) {
  v.panel_width = v.panels ? kPanel : 0;
  const OrbitRegion* region = v.region();
  draw_canvas(v, region);
  if (!v.panels) return;
  draw_legend(v);
  draw_panel(v, frame_ms);
}

}  // namespace cmr::edit
