#include "tools/edit/sources.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

#include "io/font.hpp"
#include "io/output.hpp"
#include "io/svg.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tools/edit/designer.hpp"
#include "tools/edit/editor.hpp"

namespace cmr::edit {

OpenedSource open_source(const std::filesystem::path& file, const std::string& glyph,
                         const std::filesystem::path& out_dir) {
  OpenedSource out;
  const std::string shown = file.filename().string();
  if (import::is_font_path(file)) {
    if (glyph.empty()) throw InputError(file.string() + ": a font; name the glyph to edit with --glyph X (e.g. --glyph O)");
    const std::vector<std::uint32_t> cps = import::parse_glyph_spec(glyph);
    if (cps.size() != 1) throw InputError("--glyph: expected one character (or U+hex), got '" + glyph + "'");
    const import::Font font = import::read_font(file, cps);
    if (font.glyphs.empty()) throw InputError(shown + " has no glyph for '" + glyph + "'");
    const import::Glyph& g = font.glyphs.front();
    if (g.contours.empty()) throw InputError(shown + ": glyph " + g.name + " has no contour to edit");
    for (const import::Contour& c : g.contours)
      out.curves.push_back({c.spline, c.point_names, c.spline.name(),
                            out_dir / (import::file_stem(g.name) + "_c" + std::to_string(c.index) + ".json")});
    out.what = "glyph " + g.name + " of " + shown + ": " + std::to_string(g.contours.size()) +
               (g.contours.size() == 1 ? " contour" : " contours");
    out.font = file;
    return out;
  }
  if (!glyph.empty()) throw InputError("--glyph: only for fonts, not for " + file.string());
  if (import::is_svg_path(file)) {
    const std::vector<import::PathSpline> paths = import::read_svg(file);
    if (paths.empty()) throw InputError(file.string() + ": no path to edit");
    int index = 0;
    for (const import::PathSpline& p : paths)
      out.curves.push_back({import::to_bspline(p), {}, p.name,
                            out_dir / (file.stem().string() + "_" + std::to_string(index++) + ".json")});
    out.what = shown + ": " + std::to_string(paths.size()) + (paths.size() == 1 ? " path" : " paths");
    return out;
  }
  BSpline s = read_spline_file(file);
  out.curves.push_back({std::move(s), read_point_names(file), shown, file});
  out.what = shown;
  return out;
}

}  // namespace cmr::edit

namespace cmr::edit {

void write_curve_file(const std::filesystem::path& path, const BSpline& spline, const std::vector<std::string>& names) {
  nlohmann::json doc = spline_to_json(spline);
  if (!names.empty() && static_cast<int>(names.size()) == spline.unique_point_count()) doc["point_names"] = names;
  OutputSet out;
  out.stage(path, doc.dump(2) + "\n");
  out.commit();
}

namespace {

// The view settings of `current` around another curve: P0 selected, no
// group, split, segment range or kappa-curve of the curve left behind.
Document fresh_document(const Document& current, const BSpline& spline) {
  Document next = current;
  next.spline = spline;
  next.selected = 0;
  next.group.clear();
  next.split.reset();
  next.segments.reset();
  next.kcurve.reset();
  return next;
}

}  // namespace

void Editor::set_source(OpenedSource source) {
  curves = std::move(source.curves);
  font_path = std::move(source.font);
  active_curve = 0;
  if (curves.empty()) return;
  point_names = curves[0].point_names;
  path_ = curves[0].save_as;
}

void Editor::switch_curve(int k) {
  if (k < 0 || k >= static_cast<int>(curves.size()))
    throw InputError("contour " + std::to_string(k) + ": there are " + std::to_string(curves.size()) + " curves");
  if (k == active_curve) return;
  finish_animation();
  curves[active_curve].spline = doc().spline;
  history_ = History(fresh_document(doc(), curves[k].spline));
  active_curve = k;
  point_names = curves[k].point_names;
  path_ = curves[k].save_as;
  hidden_points.clear();
  changed_document();
  region_stale_ = rgba_stale_ = true;
  message = "editing " + curves[k].name + " (" + std::to_string(k + 1) + " of " + std::to_string(curves.size()) +
            "); undo starts again here";
}

void Editor::open_glyph(const std::string& spec) {
  if (font_path.empty()) throw InputError("glyph: no font is open (cmr edit FONT --glyph X)");
  OpenedSource s = open_source(font_path, spec, curves.empty() ? "." : curves[0].save_as.parent_path());
  const std::string what = s.what;
  history_ = History(fresh_document(doc(), s.curves[0].spline));
  set_source(std::move(s));
  hidden_points.clear();
  changed_document();
  fit_view();
  message = "opened " + what;
}

void Editor::save_all() {
  if (curves.empty()) {
    save(path_);
    return;
  }
  curves[active_curve].spline = doc().spline;
  OutputSet out;  // every file, or none
  std::string list;
  for (const OpenedCurve& c : curves) {
    nlohmann::json j = spline_to_json(c.spline);
    if (!c.point_names.empty() && static_cast<int>(c.point_names.size()) == c.spline.unique_point_count())
      j["point_names"] = c.point_names;
    out.stage(c.save_as, j.dump(2) + "\n");
    list += (list.empty() ? "" : ", ") + c.save_as.string();
  }
  out.commit();
  message = "saved " + std::to_string(curves.size()) + " spline JSON files: " + list;
}

bool Editor::pick_other_curve(double x, double y) {
  for (int i = 0; i < static_cast<int>(curves.size()); ++i) {
    if (i == active_curve) continue;
    const std::vector<Vec2>& pts = curves[i].spline.points();
    for (int k = 0; k < static_cast<int>(pts.size()); ++k) {
      const Vec2 s = viewport_.to_screen(pts[k]);
      if (std::hypot(s.x - x, s.y - y) > kPickRadius) continue;
      switch_curve(i);
      select(k);
      return true;
    }
  }
  return false;
}

}  // namespace cmr::edit
