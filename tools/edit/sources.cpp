#include "tools/edit/sources.hpp"

#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>

#include "io/font.hpp"
#include "io/output.hpp"
#include "io/output_guard.hpp"
#include "io/svg.hpp"
#include "io/ufo.hpp"
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
    for (const import::Contour& c : g.contours) {
      OpenedCurve oc{c.spline, c.point_names, c.spline.name(),
                     out_dir / (import::file_stem(g.name) + "_c" + std::to_string(c.index) + ".json")};
      oc.contour = c.index;  // a line's added points are not drawn or picked here either
      oc.font_point = c.font_point;
      oc.node = c.node;
      out.curves.push_back(std::move(oc));
    }
    out.what = "glyph " + g.name + " of " + shown + ": " + std::to_string(g.contours.size()) +
               (g.contours.size() == 1 ? " contour" : " contours");
    out.font = file;
    return out;
  }
  if (import::is_ufo_path(file)) {  // a font source: a UFO folder's glyph, or one .glif
    std::string ext = (file.has_filename() ? file : file.parent_path()).extension().string();
    for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    const bool single = ext == ".glif";
    if (glyph.empty() && !single)
      throw InputError(file.string() + ": a font source; name the glyph to edit with --glyph NAME (e.g. --glyph O)");
    import::GlyphSelection which;
    if (!single) which.names = {glyph};
    const import::Font font = import::read_ufo(file, which);
    if (font.glyphs.empty()) throw InputError(shown + " has no glyph '" + glyph + "'");
    const import::Glyph& g = font.glyphs.front();
    if (single && !glyph.empty() && glyph != g.name)
      throw InputError(file.string() + ": holds the glyph '" + g.name + "', not '" + glyph + "'");
    if (!g.error.empty()) throw InputError(g.error);
    if (g.contours.empty()) throw InputError(shown + ": glyph " + g.name + " has no contour to edit");
    for (const import::Contour& c : g.contours) {
      OpenedCurve oc{c.spline, c.point_names, c.spline.name(), g.source};
      oc.contour = c.index;
      oc.font_point = c.font_point;
      oc.node = c.node;
      oc.in_source = c.spline.points();
      oc.source_knots = c.spline.knots();
      out.curves.push_back(std::move(oc));
    }
    out.what = "glyph " + g.name + " of " + shown + ": " + std::to_string(g.contours.size()) +
               (g.contours.size() == 1 ? " contour" : " contours");
    for (const std::string& n : g.notes) out.what += "; " + n;
    out.glif = g.source;
    note_read(g.source);  // as a spline file: a second editor's save is not replaced
    out.grid = 1;
    if (!single) out.font = file;
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
  note_read(file);  // a save refuses to replace it once another editor has saved it (io/output_guard.hpp)
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
  source_glif = std::move(source.glif);
  grid = source.grid;
  if (!source_glif.empty() || !font_path.empty()) legend_docked = true;  // a glyph: the legend never covers it
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
  if (!source_glif.empty()) {
    save_source();
    return;
  }
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
    const std::vector<int>& fp = curves[i].font_point;
    for (int k = 0; k < static_cast<int>(pts.size()); ++k) {
      if (!fp.empty() && fp[k % fp.size()] < 0) continue;  // a line's added point: not picked
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

namespace cmr::edit {

bool Editor::movable(int k) const {
  if (curves.empty() || active_curve >= static_cast<int>(curves.size())) return true;
  const std::vector<int>& fp = curves[active_curve].font_point;
  if (fp.empty() || static_cast<int>(fp.size()) != doc().spline.unique_point_count() || k < 0) return true;
  return fp[static_cast<std::size_t>(k) % fp.size()] >= 0;
}

std::string Editor::short_point_name(int k) const {
  std::string name = point_name(k);
  if (curves.empty() || curves[active_curve].font_point.empty()) return name;
  const std::string prefix = curves[active_curve].name + "/";
  if (name.size() > prefix.size() && name.compare(0, prefix.size(), prefix) == 0) name.erase(0, prefix.size());
  return name;
}

BSpline Editor::keep_lines(const BSpline& before, BSpline after) const {
  if (curves.empty()) return after;
  const OpenedCurve& c = curves[active_curve];
  const int m = static_cast<int>(c.font_point.size());
  if (m == 0 || m != after.unique_point_count() || m != before.unique_point_count() || !after.closed()) return after;
  const int d = after.degree();
  // The run of added points after node k (a straight piece from k to the next
  // node): put back on the segment when an end node moved.
  for (int k = 0; k < m; ++k) {
    if (!c.node[k] || c.font_point[(k + 1) % m] >= 0) continue;
    int run = 0;
    while (run < m && c.font_point[(k + 1 + run) % m] < 0) ++run;
    const int e = (k + 1 + run) % m;
    const Vec2 a = after.points()[k], b = after.points()[e];
    if (a == before.points()[k] && b == before.points()[e]) continue;
    for (int j = 1; j <= run; ++j) {
      // As io/font.cpp places them: a cubic line's inner points at k and 1-k
      // with k = 21845/65536 (exact in double for integer ends), else j/d.
      const double t = d == 3 && run == 2 ? (j == 1 ? 21845.0 / 65536.0 : 1 - 21845.0 / 65536.0)
                                          : static_cast<double>(j) / (run + 1);
      const Vec2 q = d == 3 && run == 2 && j == 2 ? b - (21845.0 / 65536.0) * (b - a) : a + t * (b - a);
      after = after.with_point((k + j) % m, q);
    }
  }
  return after;
}

std::string Editor::point_hover(double x, double y) const {
  const auto near = [&](Vec2 p) {
    const Vec2 s = viewport_.to_screen(p);
    return std::hypot(s.x - x, s.y - y) <= kPickRadius;
  };
  char buf[240];
  const std::vector<Vec2>& pts = doc().spline.points();
  for (int i = 0; i < static_cast<int>(pts.size()); ++i) {
    if (!movable(i) || !near(pts[i])) continue;
    std::snprintf(buf, sizeof buf, "%s (%.10g, %.10g)", point_name(i).c_str(), pts[i].x, pts[i].y);
    return buf;
  }
  for (int c = 0; c < static_cast<int>(curves.size()); ++c) {  // another contour's point: its full name too
    if (c == active_curve) continue;
    const OpenedCurve& oc = curves[c];
    const std::vector<Vec2>& q = oc.spline.points();
    for (int i = 0; i < oc.spline.unique_point_count(); ++i) {
      if (i < static_cast<int>(oc.font_point.size()) && oc.font_point[i] < 0) continue;
      if (!near(q[i])) continue;
      std::string name = "P";  // (built with +=: GCC 12 warns falsely on "P" + std::to_string)
      if (i < static_cast<int>(oc.point_names.size())) name = oc.point_names[i];
      else name += std::to_string(i);
      std::snprintf(buf, sizeof buf, "%s (%.10g, %.10g)", name.c_str(), q[i].x, q[i].y);
      return buf;
    }
  }
  return {};
}

void Editor::save_source() {
  if (source_glif.empty()) throw InputError("save: no font source is open");
  finish_animation();
  curves[active_curve].spline = doc().spline;
  const auto on_grid = [&](double v) { return grid > 0 ? std::round(v / grid) * grid : v; };
  std::vector<import::PointEdit> edits;
  std::vector<std::pair<int, int>> written;  // (curve, point)
  for (int i = 0; i < static_cast<int>(curves.size()); ++i) {
    const OpenedCurve& c = curves[i];
    const BSpline& s = c.spline;
    if (s.is_rational())
      throw InputError("save: " + c.name + " has weights; a .glif holds point positions only (save PATH.json keeps them)");
    if (s.point_count() != static_cast<int>(c.in_source.size()) ||
        s.knots() != c.source_knots || static_cast<int>(c.font_point.size()) != s.unique_point_count())
      throw InputError("save: " + c.name + "'s points or knots changed; a .glif holds point positions only");
    for (int k = 0; k < s.unique_point_count(); ++k) {
      if (c.font_point[k] < 0) continue;  // a line's added point: not in the source
      const Vec2 p{on_grid(s.points()[k].x), on_grid(s.points()[k].y)};
      if (p == c.in_source[k]) continue;
      edits.push_back({c.contour, c.font_point[k], p.x, p.y});
      written.emplace_back(i, k);
    }
  }
  const std::string text = read_input_file(source_glif);
  OutputSet out;  // the .glif whole, or not at all
  if (!edits.empty()) out.stage(source_glif, import::rewrite_glif_points(text, edits, source_glif.string()));
  out.commit();
  for (std::size_t j = 0; j < written.size(); ++j)
    curves[written[j].first].in_source[written[j].second] = {edits[j].x, edits[j].y};
  message = "saved " + std::to_string(edits.size()) + " moved point(s) into " + source_glif.string() +
            (grid > 0 ? " (x and y only, on the font's grid)" : " (x and y only)");
  // Rounding to the grid can undo a fix (it often lies on its region's
  // edge): say whether the view's requirement holds as saved when it held
  // before rounding.
  if (grid <= 0 || edits.empty()) return;
  const FixRequirement req = fix_requirement();
  const BSpline& s = doc().spline;
  const bool whole_period = s.closed() && !req.segments &&
                            (req.kind == FixRequirement::Kind::cmr || req.kind == FixRequirement::Kind::cmrwi);
  if (whole_period) return;  // never monotone over a whole period: nothing to say
  BSpline rounded = s;
  for (int k = 0; k < s.unique_point_count(); ++k)
    rounded = rounded.with_point(k, {std::round(s.points()[k].x / grid) * grid, std::round(s.points()[k].y / grid) * grid});
  try {
    if (!requirement_holds(s, req, doc().max_depth)) return;
    message += requirement_holds(rounded, req, doc().max_depth)
                   ? "; " + to_string(req) + " holds as saved"
                   : "; rounded to the grid, " + to_string(req) +
                         " no longer holds (cmr fix FONT.ufo --glyph NAME --require ... --in-place finds a fix on the grid)";
  } catch (const InputError&) {
    // a requirement the curve cannot be judged by: the save stands, nothing to add
  }
}

}  // namespace cmr::edit
