// The designer's read-outs without a window (tools/edit/designer.hpp): the
// legend names every colour the canvas shows in each mode, typed coordinates
// are exact, the comb fits the view, "fit" and "fit region" frame what they
// say, point names come from the file and their labels do not overprint, the
// curve under the cursor and the certified extrema of the segment table.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "io/font.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tools/edit/designer.hpp"

namespace {

using namespace cmr;
using namespace cmr::edit;
namespace fs = std::filesystem;

const std::string kFig8 = std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8.json";
const std::string kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

Editor editor_of(const BSpline& s, int w = 240, int h = 180, bool ui = false) {
  Editor e(s, "t.json", w, h);
  e.show_ui = ui;
  e.fit_view();
  return e;
}

/// The outer contour of DejaVu Sans's "O" (a closed quadratic), with its names.
std::optional<import::Contour> glyph_contour() {
  if (!fs::exists(kFont)) return std::nullopt;
  import::Font f = import::read_font(kFont, {'O'});
  if (f.glyphs.empty() || f.glyphs[0].contours.empty()) return std::nullopt;
  return f.glyphs[0].contours[0];
}

/// Checks that every colour of the canvas is named by the legend: a swatch
/// of that exact colour, or a gradient (depth shading) whose ends bound it.
/// Returns how many distinct colours were shown.
int expect_legend_names_every_colour(Editor& e, const std::string& mode) {
  const std::vector<uint8_t>& rgba = e.region_rgba();
  const Legend l = region_legend(e);
  std::set<std::array<int, 3>> shown;
  const auto [cw, ch] = e.canvas();
  for (int j = 0; j < ch; ++j)
    for (int i = 0; i < cw; ++i) {
      const std::size_t at = (static_cast<std::size_t>(j) * e.viewport().width + i) * 4;
      shown.insert({rgba[at], rgba[at + 1], rgba[at + 2]});
    }
  for (const auto& c : shown) {
    bool named = false;
    for (const LegendLine& x : l.lines) {
      if (x.kind == LegendLine::Kind::swatch && bytes_of(x.colour) == c) named = true;
      if (x.kind == LegendLine::Kind::gradient) {
        const auto a = bytes_of(x.colour), b = bytes_of(x.colour_to);
        bool inside = true;
        for (int k = 0; k < 3; ++k) inside = inside && c[k] >= std::min(a[k], b[k]) - 1 && c[k] <= std::max(a[k], b[k]) + 1;
        // on the line from a to b: the channels move together
        if (inside) named = true;
      }
    }
    EXPECT_TRUE(named) << mode << ": colour " << c[0] << "," << c[1] << "," << c[2] << " is not in the legend";
  }
  EXPECT_FALSE(l.title.empty()) << mode;
  return static_cast<int>(shown.size());
}

TEST(EditLegend, NamesEveryColourShownInEachMode) {
  const BSpline s = read_spline_file(kFig8);
  Editor e = editor_of(s);
  e.set_view({-1, -7, 5, -2.5});  // around P3: increasing and decreasing pixels
  e.select(3);
  EXPECT_GE(expect_legend_names_every_colour(e, "cmrwi"), 2);
  e.set_mode(Mode::cmr);
  EXPECT_GE(expect_legend_names_every_colour(e, "cmr"), 1);
  e.set_mode(Mode::cmrwi);
  e.set_split(2);
  EXPECT_GE(expect_legend_names_every_colour(e, "split 2"), 2);
  const Legend split = region_legend(e);
  EXPECT_NE(split.title.find("split at joint 2"), std::string::npos) << split.title;
  e.set_split(std::nullopt);
  e.set_chain(true);
  EXPECT_GE(expect_legend_names_every_colour(e, "each piece"), 1);
  EXPECT_NE(region_legend(e).title.find("every piece"), std::string::npos);
  e.set_chain(false);
  e.set_depth_shading(true);
  EXPECT_GE(expect_legend_names_every_colour(e, "depth shading"), 3);
  const Legend shaded = region_legend(e);
  EXPECT_TRUE(std::any_of(shaded.lines.begin(), shaded.lines.end(),
                          [](const LegendLine& x) { return x.kind == LegendLine::Kind::gradient; }));
  e.set_depth_shading(false);
  e.set_all_points(true);
  EXPECT_GE(expect_legend_names_every_colour(e, "all points"), 2);
  // Every point's outline hue is in the legend, under its name; a hidden
  // point's region and legend line go.
  Legend all = region_legend(e);
  for (int k = 0; k < 6; ++k) {
    std::string want = "P";  // (built with +=: GCC 12 warns falsely on "P" + std::to_string)
    want += std::to_string(k);
    want += "'s region";
    EXPECT_TRUE(std::any_of(all.lines.begin(), all.lines.end(), [&](const LegendLine& x) {
      return x.kind == LegendLine::Kind::outline && x.point == k && x.text.rfind(want, 0) == 0 &&
             bytes_of(x.colour) == bytes_of(draw::point_colour(k));
    })) << "P" << k;
  }
  e.set_point_shown(3, false);
  EXPECT_EQ(e.layer_points(), (std::vector<int>{0, 1, 2, 4, 5}));
  EXPECT_EQ(e.region().size(), 5u);
  all = region_legend(e);
  EXPECT_FALSE(std::any_of(all.lines.begin(), all.lines.end(), [](const LegendLine& x) { return x.point == 3; }));
  expect_legend_names_every_colour(e, "all points but P3");
  EXPECT_THROW(e.set_point_shown(6, true), InputError);
}

TEST(EditNumbers, TypedCoordinatesAreExact) {
  Editor e = editor_of(read_spline_file(kFig8));
  const BSpline before = e.doc().spline;
  const double x = std::stod("2.123456789012345"), y = std::stod("-4.4400000000000004");
  e.set_point_xy(3, x, y);
  const Vec2 p = e.doc().spline.points()[3];
  EXPECT_EQ(p.x, x);  // bit for bit
  EXPECT_EQ(p.y, y);
  for (int k = 0; k < 6; ++k)
    if (k != 3) {
      EXPECT_EQ(e.doc().spline.points()[k], before.points()[k]) << k;
    }
  EXPECT_TRUE(e.undo());
  EXPECT_EQ(e.doc().spline.points(), before.points()) << "one undo step";
  EXPECT_THROW(e.set_point_xy(3, NAN, 0), InputError);
  EXPECT_THROW(e.set_point_xy(9, 0, 0), InputError);
}

/// Every tooth's tip inside the canvas's view (zoomed in: every tooth whose
/// foot is in the view, kCombMargin from its edge; the others belong to the
/// part of the curve out of view).
void expect_comb_fits(Editor& e, const std::string& what, bool zoomed = false) {
  const View v = canvas_view(e);
  const Comb c = comb_geometry(e.doc().spline, v, 1.0, e.comb_density);
  ASSERT_FALSE(c.tips.empty()) << what;
  ASSERT_GT(c.fit_unit, 0) << what;
  int outside = 0;
  const double mx = kCombMargin * (v.x1 - v.x0), my = kCombMargin * (v.y1 - v.y0);
  for (std::size_t i = 0; i < c.tips.size(); ++i) {
    const Vec2 t = c.tips[i], f = c.feet[i];
    const bool foot_in = f.x > v.x0 + mx && f.x < v.x1 - mx && f.y > v.y0 + my && f.y < v.y1 - my;
    if (zoomed && !foot_in) continue;
    EXPECT_TRUE(zoomed || foot_in) << what << ": the fitted view shows the whole curve, tooth " << i;
    if (!(t.x >= v.x0 && t.x <= v.x1 && t.y >= v.y0 && t.y <= v.y1) && ++outside <= 3)
      ADD_FAILURE() << what << ": tooth " << i << " ends at (" << t.x << ", " << t.y << ") outside the view";
  }
  // The comb is not degenerate: its longest tooth is a visible part of the view.
  double longest = 0;
  for (std::size_t i = 0; i < c.tips.size(); ++i) longest = std::max(longest, std::hypot(c.tips[i].x - c.feet[i].x, c.tips[i].y - c.feet[i].y));
  EXPECT_GT(longest, 0.03 * std::min(v.x1 - v.x0, v.y1 - v.y0)) << what;
}

TEST(EditComb, FitsTheViewOnFig8AndOnAGlyph) {
  for (const bool ui : {false, true}) {
    Editor e = editor_of(read_spline_file(kFig8), 1024, 768, ui);
    expect_comb_fits(e, std::string("fig8") + (ui ? " with panels" : ""));
    // Zoomed in on P3 (the curve leaves the view): the teeth whose feet are in
    // view still end inside it.
    e.set_view({-1, -7, 5, -2.5});
    expect_comb_fits(e, "fig8 zoomed", true);
    e.comb_density = 80;
    expect_comb_fits(e, "fig8 dense", true);
  }
  const auto o = glyph_contour();
  if (!o) GTEST_SKIP() << kFont << " is missing (fonts-dejavu-core)";
  Editor g = editor_of(o->spline, 1024, 768, true);
  expect_comb_fits(g, "glyph O");
  // Scale 1 is the fit: twice as long leaves the view somewhere.
  const View v = canvas_view(g);
  const Comb twice = comb_geometry(g.doc().spline, v, 2.0, g.comb_density);
  EXPECT_TRUE(std::any_of(twice.tips.begin(), twice.tips.end(), [&](Vec2 t) {
    return t.x < v.x0 + kCombMargin * (v.x1 - v.x0) * 0.99 || t.x > v.x1 - kCombMargin * (v.x1 - v.x0) * 0.99 ||
           t.y < v.y0 + kCombMargin * (v.y1 - v.y0) * 0.99 || t.y > v.y1 - kCombMargin * (v.y1 - v.y0) * 0.99;
  }));
}

TEST(EditViews, FitFramesCurveCombAndRegionAndFitRegionZoomsOntoIt) {
  Editor e = editor_of(read_spline_file(kFig8), 640, 480, true);
  e.select(3);
  e.fit_view();
  const View v = canvas_view(e);
  for (const Vec2& p : e.doc().spline.points()) {
    EXPECT_GE(p.x, v.x0);
    EXPECT_LE(p.x, v.x1);
    EXPECT_GE(p.y, v.y0);
    EXPECT_LE(p.y, v.y1);
  }
  expect_comb_fits(e, "after fit");
  // The region's box on the coarse grid of "fit" lies in the view.
  const auto box = region_box(e, 1.0, 96);
  ASSERT_TRUE(box.has_value());
  // fit region: the region fills a good part of the canvas and its monotone
  // pixels do not run off a side that a view 4 times larger shows closed.
  const auto wide = region_box(e, 4.0, 128);
  ASSERT_TRUE(wide.has_value());
  e.fit_region();
  EXPECT_NE(e.message.find("framed P3's region"), std::string::npos) << e.message;
  const View f = canvas_view(e);
  EXPECT_LE(f.x0, wide->first.x);
  EXPECT_GE(f.x1, wide->second.x);
  EXPECT_LE(f.y0, wide->first.y);
  EXPECT_GE(f.y1, wide->second.y);
  const std::vector<const RegionResult*>& layers = e.region();
  ASSERT_EQ(layers.size(), 1u);
  std::size_t inside = 0;
  for (std::size_t i = 0; i < layers[0]->size(); ++i) inside += layers[0]->in_region(i);
  EXPECT_GT(inside, layers[0]->size() / 50) << "the region shows large after fit region";
  // Far from the curve nothing of P0's region shows: said, and the view kept.
  e.select(0);
  e.set_view({1e6, 1e6, 1e6 + 1, 1e6 + 0.75});
  const View before = e.viewport().view;
  e.fit_region();
  if (e.message.find("empty") != std::string::npos) {
    EXPECT_EQ(e.viewport().view.x0, before.x0);
    EXPECT_EQ(e.viewport().view.y1, before.y1);
  }
}

TEST(EditNames, FromTheFileAndLabelsDoNotOverprint) {
  const auto o = glyph_contour();
  if (!o) GTEST_SKIP() << kFont << " is missing";
  const fs::path f = fs::temp_directory_path() / "cmr_edit_designer_O.json";
  std::ofstream(f) << import::contour_json(*o).dump();
  const std::vector<std::string> names = read_point_names(f);
  ASSERT_EQ(names, o->point_names);
  Editor e = editor_of(read_spline_file(f));
  e.point_names = names;
  const int m = e.doc().spline.unique_point_count();
  for (int k = 0; k < e.doc().spline.point_count(); ++k) EXPECT_EQ(e.point_name(k), names[k % m]) << k;
  EXPECT_EQ(read_point_names(kFig8), std::vector<std::string>{});
  // Every point overlapped on a closed contour: one layer per distinct point.
  e.set_all_points(true);
  std::vector<int> distinct(m);
  for (int k = 0; k < m; ++k) distinct[k] = k;
  EXPECT_EQ(e.layer_points(), distinct);
  Editor plain = editor_of(read_spline_file(kFig8));
  EXPECT_EQ(plain.point_name(4), "P4");
  // Crowded points: no two labels overlap, none covers a point marker.
  std::vector<Vec2> pts, sizes;
  for (int i = 0; i < 40; ++i) {
    pts.push_back({100 + 7.0 * (i % 8), 100 + 9.0 * (i / 8)});
    sizes.push_back({40, 13});
  }
  const std::vector<PlacedLabel> placed = place_labels(pts, sizes, 6);
  EXPECT_GT(placed.size(), 5u);
  for (std::size_t a = 0; a < placed.size(); ++a) {
    for (std::size_t b = a + 1; b < placed.size(); ++b) {
      const PlacedLabel &p = placed[a], &q = placed[b];
      EXPECT_FALSE(p.x < q.x + q.w && q.x < p.x + p.w && p.y < q.y + q.h && q.y < p.y + p.h) << a << " " << b;
    }
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (static_cast<int>(i) == placed[a].point) continue;
      const PlacedLabel& p = placed[a];
      EXPECT_FALSE(pts[i].x + 6 > p.x && pts[i].x - 6 < p.x + p.w && pts[i].y + 6 > p.y && pts[i].y - 6 < p.y + p.h);
    }
  }
  // Apart, every point keeps its label.
  std::vector<Vec2> apart = {{10, 10}, {200, 10}, {10, 200}};
  EXPECT_EQ(place_labels(apart, {{30, 13}, {30, 13}, {30, 13}}, 6).size(), 3u);
}

TEST(EditNumbers, CurveUnderTheCursorAndCertifiedExtrema) {
  Editor e = editor_of(read_spline_file(kFig8), 640, 480);
  const BSpline& s = e.doc().spline;
  for (const double t : {2.3, 3.5, 4.6}) {
    const Vec2 at = e.viewport().to_screen(evaluate(s, t));
    const auto pick = pick_curve(s, e.viewport(), at.x + 0.5, at.y - 0.5, 8);
    ASSERT_TRUE(pick.has_value()) << t;
    EXPECT_NEAR(pick->t, t, 0.02) << "the nearest curve point";
    EXPECT_NEAR(pick->kappa, curvature(s, pick->t), 1e-12);
  }
  EXPECT_FALSE(pick_curve(s, e.viewport(), -500, -500, 8).has_value());
  // The segment table's extrema are the report's certified ones: Fig. 8 has
  // its flattest and sharpest points in segments 0 and 1 (the dip).
  const CurvatureEvents& ev = e.events();
  ASSERT_EQ(ev.extrema.size(), ev.maxima.size() + ev.minima.size() +
                                   static_cast<std::size_t>(std::count_if(ev.extrema.begin(), ev.extrema.end(),
                                                                          [](const auto& x) { return x.kind == 2; })));
  bool flat0 = false, sharp1 = false;
  for (const auto& x : ev.extrema) {
    EXPECT_NEAR(x.kappa, curvature(s, x.t), 1e-6 * std::max(1.0, std::abs(x.kappa)));
    flat0 = flat0 || (x.kind == 1 && x.segment == 0);
    sharp1 = sharp1 || (x.kind == 0 && x.segment == 1);
  }
  EXPECT_TRUE(flat0);
  EXPECT_TRUE(sharp1);
  // Joint markers: fig8's uniform cubic joints are C2, so G2.
  for (const Joint& j : e.analysis().joints) EXPECT_EQ(joint_continuity(j), 2) << j.index;
}

TEST(EditConstrainedDrag, StopsAtTheRegionsBoundaryOnACertifiedPosition) {
  Editor e = editor_of(read_spline_file(kFig8), 640, 480);
  e.select(3);
  e.set_view({-1, -7, 5, -2.5});
  // P3 onto a pixel deep inside its region (all its neighbours inside too).
  const RegionResult& layer = *e.region().front();
  const RegionRequest rq = e.region_requests().front();
  std::optional<Vec2> deep;
  for (int j = 3; j < layer.height - 3 && !deep; ++j)
    for (int i = 3; i < layer.width - 3 && !deep; ++i) {
      bool all = true;
      for (int dj = -3; dj <= 3; ++dj)
        for (int di = -3; di <= 3; ++di) all = all && layer.in_region(static_cast<std::size_t>(j + dj) * layer.width + i + di);
      if (all) deep = pixel_center(*rq.view, rq.width, rq.height, i, j);
    }
  ASSERT_TRUE(deep.has_value());
  e.move_point(3, *deep);
  const Vec2 start = e.doc().spline.points()[3];
  ASSERT_TRUE(e.in_selected_region(start));
  const Vec2 target = start + Vec2{4, 3};  // far out of the region
  ASSERT_FALSE(e.in_selected_region(target));
  const auto drag = [&](Vec2 to) {
    const Vec2 a = e.viewport().to_screen(e.doc().spline.points()[3]), b = e.viewport().to_screen(to);
    e.mouse_move(a.x, a.y);
    e.mouse_button(MouseButton::left, true, false);
    for (int i = 1; i <= 5; ++i) e.mouse_move(a.x + (b.x - a.x) * i / 5, a.y + (b.y - a.y) * i / 5);
    e.mouse_button(MouseButton::left, false, false);
  };
  e.constrain_drag = true;
  drag(target);
  const Vec2 end = e.doc().spline.points()[3];
  EXPECT_TRUE(e.in_selected_region(end)) << "certified inside: " << end.x << ", " << end.y;
  EXPECT_GT(std::hypot(end.x - target.x, end.y - target.y), 0.1) << "it stopped short of the pointer";
  // At the boundary: a hair further towards the pointer is outside.
  const Vec2 dir = target - end;
  const double len = std::hypot(dir.x, dir.y);
  EXPECT_FALSE(e.in_selected_region(end + dir * (1e-6 / len))) << "it stopped at the boundary, not before";
  // Every other point is where it was; unconstrained, the drag follows the pointer.
  EXPECT_TRUE(e.undo());
  e.constrain_drag = false;
  drag(target);
  const Vec2 free = e.doc().spline.points()[3];
  EXPECT_NEAR(free.x, target.x, 1e-6);
  EXPECT_NEAR(free.y, target.y, 1e-6);
}

}  // namespace
