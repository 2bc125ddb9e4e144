// cmr region --contours and cmr sweep, run as a user runs them; the files are
// read back with OpenMesh's readers and compared with the library's own
// computation in this process.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // in OpenMesh's headers (see draw/mesh.hpp)
#include <OpenMesh/Core/IO/MeshIO.hh>
#pragma GCC diagnostic pop

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bezierize/knot_ops.hpp"
#include "spline/spline_json.hpp"
#include "tests/cli_util.hpp"
#include "draw/draw.hpp"
#include "draw/mesh.hpp"

#include <cairo.h>

namespace cmr::test {
namespace {

const std::string kFig8 = std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8.json";
const std::string kView = "-0.1,-5.4,3.0,-2.3";

mesh::Mesh read_mesh(const fs::path& p) {
  mesh::Mesh m;
  EXPECT_TRUE(OpenMesh::IO::read_mesh(m, p.string())) << p;
  return m;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path d = scratch() / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// The OBJ and PLY of `cmr region --contours` hold the mesh the library builds
// from the same region: same vertex and face counts, same area (to the float
// precision of OpenMesh's readers), and the summary's areas are the contours'.
TEST(RegionContoursCli, ObjPlySvgMatchTheLibrary) {
  const fs::path d = fresh_dir("contours");
  const std::string common = kFig8 + " --point 3 --backend cpu --size 48x40 --view " + kView;
  const Outcome obj = run("region " + common + " --contours " + (d / "r.obj").string());
  ASSERT_EQ(obj.code, 0) << obj.err;
  ASSERT_EQ(run("region " + common + " --contours " + (d / "r.ply").string()).code, 0);
  ASSERT_EQ(run("region " + common + " --contours " + (d / "r.svg").string()).code, 0);

  RegionRequest rq;
  rq.point = 3;
  rq.width = 48;
  rq.height = 40;
  rq.view = View{-0.1, -5.4, 3.0, -2.3};
  const RegionProblem problem = RegionProblem::make(read_spline_file(kFig8), rq);
  CpuRegionBackend cpu(2);
  const RegionResult img = cpu.render(problem);
  const RegionContours rc = region_contours(problem, img);
  const mesh::Mesh expected = mesh::region_mesh(rc);
  ASSERT_GT(expected.n_vertices(), 100u);

  const nlohmann::json summary = nlohmann::json::parse(obj.out);
  const nlohmann::json& areas = summary["points"][0]["areas"];
  ASSERT_EQ(areas.size(), rc.labels.size() + 1);  // and the undecided band
  for (const LabelContours& lc : rc.labels) EXPECT_EQ(areas[img.label_name(lc.label)].get<double>(), lc.area);
  EXPECT_EQ(areas[kUndecidedBandName].get<double>(), rc.band.area);

  for (const char* name : {"r.obj", "r.ply"}) {
    const mesh::Mesh m = read_mesh(d / name);
    EXPECT_EQ(m.n_vertices(), expected.n_vertices()) << name;
    EXPECT_EQ(m.n_faces(), expected.n_faces()) << name;
    EXPECT_NEAR(mesh::mesh_area(m), mesh::mesh_area(expected), 1e-5 * mesh::mesh_area(expected)) << name;
  }
  EXPECT_EQ(slurp(d / "r.svg"), mesh::contours_svg(rc));
}

// The reproducer: at 40x40 no pixel centre is undecided, yet a band
// undecided at depth 12 separates increasing from not monotone; it is an
// outline of its own in the SVG and an `areas` entry of its own.
TEST(RegionContoursCli, UndecidedBandIsAnOutlineAndAnArea) {
  const fs::path d = fresh_dir("contours_band");
  const Outcome r = run("region " + kFig8 + " --point 3 --backend cpu --size 40x40 --view " + kView + " --contours " +
                        (d / "c.svg").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json p = nlohmann::json::parse(r.out)["points"][0];
  EXPECT_EQ(p["counts"]["undecided"], 0) << p;
  ASSERT_TRUE(p["areas"].contains(kUndecidedBandName)) << p;
  EXPECT_GT(p["areas"][kUndecidedBandName].get<double>(), 0) << p;
  EXPECT_NE(slurp(d / "c.svg").find("data-name=\"undecided-band\""), std::string::npos);
}

TEST(RegionContoursCli, BadExtensionIsRefusedBeforeAnyFile) {
  const fs::path d = fresh_dir("contours_bad");
  const Outcome r = run("region " + kFig8 + " --point 3 --backend cpu --size 16x16 --png " + (d / "r.png").string() +
                        " --contours " + (d / "r.stl").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find(".svg, .obj or .ply"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(d));
}

// A small sweep of the paper's interior knot (fig8, knot 3 = 3 between 2.6
// and 3.2): every output is there, the JSON lines carry the contours' areas,
// and the tube read back from tube.obj / tube.ply is the closed mesh the
// library builds from the same label maps, with the vertex count and area
// the summary reports.
TEST(SweepCli, InteriorKnotSweepWritesEverythingAndTheTubeChecksOut) {
  const fs::path d = fresh_dir("sweep");
  const Outcome r = run("sweep " + kFig8 + " --point 3 --knot 3 --from 2.6 --to 3.2 --steps 3 --size 32x32 --view " +
                        kView + " --out-dir " + d.string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::vector<nlohmann::json> records;
  for (std::string line; std::getline(lines, line);) records.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(records.size(), 5u);  // 4 steps and the summary
  EXPECT_EQ(slurp(d / "steps.jsonl"), r.out.substr(0, r.out.rfind("{\"out_dir\"")));
  for (int s = 0; s < 4; ++s) {
    char name[32];
    std::snprintf(name, sizeof name, "step_%03d", s);
    EXPECT_TRUE(fs::exists(d / "contours" / (std::string(name) + ".svg"))) << name;
    EXPECT_TRUE(fs::exists(d / "frames" / (std::string(name) + ".png"))) << name;
  }
  for (const char* f : {"area.png", "index.html", "tube.obj", "tube.ply"}) EXPECT_TRUE(fs::exists(d / f)) << f;

  // The same steps in this process.
  const BSpline base = read_spline_file(kFig8);
  RegionRequest rq;
  rq.point = 3;
  rq.width = rq.height = 32;
  rq.view = View{-0.1, -5.4, 3.0, -2.3};
  rq.depth = false;
  mesh::VoxelStack stack{32, 32, *rq.view, {}, {}};
  CpuRegionBackend cpu(2);
  for (int s = 0; s < 4; ++s) {
    const double u = s == 3 ? 3.2 : 2.6 + (3.2 - 2.6) * (s / 3.0);  // as cmd_sweep.cpp
    EXPECT_EQ(records[s]["value"].get<double>(), u);
    const RegionProblem problem = RegionProblem::make(set_knot(base, 3, u), rq);
    const RegionResult img = cpu.render(problem);
    const RegionContours rc = region_contours(problem, img);
    double monotone = 0;
    for (const LabelContours& lc : rc.labels) {
      EXPECT_EQ(records[s]["areas"][img.label_name(lc.label)].get<double>(), lc.area);
      if (lc.label == 1 || lc.label == 2) monotone += lc.area;
    }
    EXPECT_EQ(records[s]["monotone_area"].get<double>(), monotone);
    stack.knots.push_back(u);
    for (std::size_t i = 0; i < img.size(); ++i) stack.in.push_back(img.code_at(i) == 1 || img.code_at(i) == 2);
  }
  const mesh::Mesh tube = mesh::tube_mesh(stack);
  ASSERT_GT(tube.n_vertices(), 100u);
  EXPECT_TRUE(mesh::is_closed(tube));
  const nlohmann::json& summary = records.back()["tube"];
  EXPECT_EQ(summary["vertices"].get<std::size_t>(), tube.n_vertices());
  EXPECT_EQ(summary["faces"].get<std::size_t>(), tube.n_faces());
  EXPECT_EQ(summary["area"].get<double>(), mesh::mesh_area(tube));
  EXPECT_TRUE(summary["closed"].get<bool>());
  for (const char* name : {"tube.obj", "tube.ply"}) {
    const mesh::Mesh m = read_mesh(d / name);
    EXPECT_EQ(m.n_vertices(), tube.n_vertices()) << name;
    EXPECT_EQ(m.n_faces(), tube.n_faces()) << name;
    EXPECT_TRUE(mesh::is_closed(m)) << name;
    EXPECT_NEAR(mesh::mesh_area(m), mesh::mesh_area(tube), 1e-5 * mesh::mesh_area(tube)) << name;
  }
}

// Uniform to clamped (the paper's two knot vectors, Figs. 8 and 9) in one
// sweep of the whole knot vector: the last step has the clamped knots.
TEST(SweepCli, UniformToClampedEndsOnTheClampedKnots) {
  const Outcome r = run("sweep " + std::string(CMR_SOURCE_DIR) +
                        "/examples/sweep/fig9_uniform.json --point 3 --to-knots 0,0,0,1,2,3,3,3 --steps 2 --size 16x16");
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line, last;
  int n = 0;
  while (std::getline(lines, line)) last = line, ++n;
  EXPECT_EQ(n, 3);
  EXPECT_EQ(nlohmann::json::parse(last)["knots"], nlohmann::json::parse("[0,0,0,1,2,3,3,3]"));
}

TEST(SweepCli, InvalidStepIsRefusedBeforeAnyOutput) {
  const fs::path d = fresh_dir("sweep_bad");
  // Knot 3 may not pass knot 4 (= 4).
  const Outcome r = run("sweep " + kFig8 + " --point 3 --knot 3 --from 3 --to 5 --steps 4 --size 8x8 --out-dir " +
                        d.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("step 3"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
  EXPECT_TRUE(fs::is_empty(d));
  EXPECT_EQ(run("sweep " + kFig8 + " --knot 3 --from 3 --to 3.5 --steps 0").code, 2);
  EXPECT_EQ(run("sweep " + kFig8 + " --knot 3 --steps 2").code, 2);
  EXPECT_EQ(run("sweep " + kFig8 + " --to-knots 0,1 --steps 2").code, 2);
}

}  // namespace
// Without --view the sweep's view is the union of its steps' regions and the
// moved point, with a margin (issue 40 item 6): P3 lies inside it, the
// largest step's region fills at least a tenth of the frame, and a rerun
// with that view given as --view writes the same steps.
TEST(SweepCli, DefaultViewIsTheUnionOfTheRegionsAndTheMovedPoint) {
  const fs::path dir = scratch() / "sweep_fitted", again = scratch() / "sweep_fitted_again";
  const std::string args = "sweep " + kFig8 + " --point 3 --knot 3 --from 2.6 --to 3.2 --steps 3 --size 40x40 --out-dir ";
  const Outcome r = run(args + dir.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json summary = nlohmann::json::parse(r.out.substr(r.out.rfind("{\"out_dir\"")));
  const auto& v = summary["view"];
  const nlohmann::json p3 = nlohmann::json::parse(slurp(kFig8))["points"][3];
  EXPECT_GT(p3[0].get<double>(), v[0].get<double>());
  EXPECT_LT(p3[0].get<double>(), v[2].get<double>());
  EXPECT_GT(p3[1].get<double>(), v[1].get<double>());
  EXPECT_LT(p3[1].get<double>(), v[3].get<double>());
  std::istringstream lines(slurp(dir / "steps.jsonl"));
  std::size_t largest = 0;
  for (std::string line; std::getline(lines, line);) {
    const auto c = nlohmann::json::parse(line)["counts"];
    largest = std::max(largest, c["increasing"].get<std::size_t>() + c["decreasing"].get<std::size_t>());
  }
  EXPECT_GE(largest * 10, 40u * 40u);
  std::ostringstream view;
  view.precision(17);
  view << " --view " << v[0].get<double>() << "," << v[1].get<double>() << "," << v[2].get<double>() << ","
       << v[3].get<double>();
  const Outcome r2 = run(args + again.string() + view.str());
  ASSERT_EQ(r2.code, 0) << r2.err;
  EXPECT_EQ(slurp(dir / "steps.jsonl"), slurp(again / "steps.jsonl"));
  fs::remove_all(dir);
  fs::remove_all(again);
}

namespace {

/// A PNG read back with Cairo: pixel (x, y) as {r, g, b}, 0..255.
struct Picture {
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface{nullptr, cairo_surface_destroy};
  int width = 0, height = 0;
  std::array<int, 3> at(int x, int y) const {
    const unsigned char* row = cairo_image_surface_get_data(surface.get()) +
                               static_cast<std::ptrdiff_t>(y) * cairo_image_surface_get_stride(surface.get());
    const std::uint32_t p = reinterpret_cast<const std::uint32_t*>(row)[x];  // native-endian ARGB32
    return {static_cast<int>((p >> 16) & 255), static_cast<int>((p >> 8) & 255), static_cast<int>(p & 255)};
  }
};

Picture read_picture(const fs::path& p) {
  Picture pic;
  pic.surface.reset(cairo_image_surface_create_from_png(p.c_str()));
  EXPECT_EQ(cairo_surface_status(pic.surface.get()), CAIRO_STATUS_SUCCESS) << p;
  cairo_surface_flush(pic.surface.get());
  pic.width = cairo_image_surface_get_width(pic.surface.get());
  pic.height = cairo_image_surface_get_height(pic.surface.get());
  return pic;
}

/// The mean x of the ruler's red mark (the strip's rows, red and not the
/// regions' light red), or -1 when there is none.
double red_mark_x(const Picture& p) {
  double sum = 0;
  int n = 0;
  for (int y = 4; y < 28; ++y)
    for (int x = 0; x < p.width; ++x)
      if (const auto c = p.at(x, y); c[0] > 170 && c[1] < 70 && c[2] < 70) sum += x, ++n;
  return n == 0 ? -1 : sum / n;
}

}  // namespace

// Issue 40 item 6: every frame carries a knot ruler whose red mark sits at
// the moving knot's value on a scale shared by all frames; every step has a
// kappa plot and, where its region is empty or full, the reason; the page's
// area plot gets a marker whose mapping (the page's `plot` object) puts
// each step on the drawn total-area curve.
TEST(SweepCli, FramesCarryAKnotRulerAndThePageMarksTheStepOnTheAreaPlot) {
  const fs::path d = fresh_dir("sweep_ruler");
  const Outcome r = run("sweep " + kFig8 + " --point 3 --knot 3 --from 2.1 --to 3.9 --steps 6 --size 160x160 --view " +
                        kView + " --out-dir " + d.string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream lines(slurp(d / "steps.jsonl"));
  std::vector<nlohmann::json> records;
  for (std::string line; std::getline(lines, line);) records.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(records.size(), 7u);
  // fig8's knots are 0..7 and knot 3 stays inside them: the ruler spans [0, 7].
  draw::KnotRuler ruler;
  ruler.from = 0, ruler.to = 7;
  const draw::RulerGeometry g = draw::knot_ruler_geometry(160);
  std::vector<double> marks;
  int with_reason = 0;
  for (std::size_t s = 0; s < records.size(); ++s) {
    char name[32];
    std::snprintf(name, sizeof name, "step_%03zu.png", s);
    const Picture frame = read_picture(d / "frames" / name);
    ASSERT_EQ(frame.width, 160);
    const double u = records[s]["value"].get<double>(), x = red_mark_x(frame);
    EXPECT_NEAR(x, g.x(ruler, u), 2.0) << name << ": the red mark for knot 3 = " << u;
    marks.push_back(x);
    EXPECT_TRUE(fs::exists(d / "kappa" / name)) << name;
    // A reason exactly where the region is empty (or full) in the view.
    const auto& c = records[s]["counts"];
    const std::size_t in = c["increasing"].get<std::size_t>() + c["decreasing"].get<std::size_t>();
    EXPECT_EQ(records[s].contains("reason"), in == 0 || in == 160u * 160u) << name << ": " << records[s].dump();
    with_reason += records[s].contains("reason");
  }
  EXPECT_GT(marks.back() - marks.front(), 0.2 * (g.x1 - g.x0)) << "the mark moves with the knot";
  EXPECT_GE(with_reason, 1) << "the sweep passes steps where P3's region vanishes (docs/sweep.md)";
  EXPECT_NE(slurp(d / "kappa" / "step_000.png"), slurp(d / "kappa" / "step_006.png"));

  const std::string html = slurp(d / "index.html");
  for (const char* part : {"id=\"mark\"", "id=\"kappa\"", "'kappa/step_'", "markAt(r.value)"})
    EXPECT_NE(html.find(part), std::string::npos) << part;
  const std::size_t at = html.find("const plot = ");
  ASSERT_NE(at, std::string::npos);
  const std::size_t from = at + 13;
  const nlohmann::json plot = nlohmann::json::parse(html.substr(from, html.find(";\n", from) - from));
  const auto num = [&](const char* key) { return plot.at(key).get<double>(); };
  const draw::PlotArea area{plot.at("width").get<int>(), plot.at("height").get<int>(), num("left"), num("right"),
                            num("top"), num("bottom"), num("x0"), num("x1"), num("y0"), num("y1")};
  const Picture png = read_picture(d / "area.png");
  ASSERT_EQ(png.width, area.width);
  ASSERT_EQ(png.height, area.height);
  for (const nlohmann::json& rec : records) {
    // The total-area curve (black, drawn under the label's series where they are equal) passes
    // within 3 px of the marked step's point: a pixel there is neither white nor the grid's grey.
    const int px = static_cast<int>(std::lround(area.px(rec["value"].get<double>())));
    const int py = static_cast<int>(std::lround(area.py(rec["monotone_area"].get<double>())));
    bool dark = false;
    for (int y = std::max(0, py - 3); y <= std::min(png.height - 1, py + 3); ++y)
      for (int x = std::max(0, px - 3); x <= std::min(png.width - 1, px + 3); ++x)
        if (const auto c = png.at(x, y); std::min({c[0], c[1], c[2]}) < 150) dark = true;
    EXPECT_TRUE(dark) << "step " << rec["step"] << ": no curve at (" << px << ", " << py << ") of area.png";
  }
}

}  // namespace cmr::test
