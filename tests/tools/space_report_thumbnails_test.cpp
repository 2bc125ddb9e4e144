// The region thumbnails of `cmr report` for space curves (issue 25,
// report/space_report.hpp, docs/space.md): one per control point, its region
// in its default plane, the picture and labels of `cmr region FILE --point K`
// (no --plane) at the same size and depth.
#include <gtest/gtest.h>

#include <algorithm>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "report/space_report.hpp"
#include "tests/cli_util.hpp"

namespace cmr {
namespace {

using test::run;
using test::write;

const std::string kSpace = std::string(CMR_SOURCE_DIR) + "/examples/space/";

std::string base64_decode(const std::string& text) {
  static const std::string kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::uint32_t bits = 0;
  int n = 0;
  for (char c : text) {
    if (c == '=') break;
    const std::size_t v = kAlphabet.find(c);
    if (v == std::string::npos) ADD_FAILURE() << "not base64: " << c;
    bits = (bits << 6) | static_cast<std::uint32_t>(v);
    n += 6;
    if (n >= 8) {
      n -= 8;
      out += static_cast<char>((bits >> n) & 0xff);
    }
  }
  return out;
}

struct Thumb {
  int point;
  std::string alt, png;
};

std::vector<Thumb> thumbnails(const std::string& html) {
  std::vector<Thumb> out;
  const std::regex img("<img alt=\"(region of P([0-9]+)[^\"]*)\" width=\"[0-9]+\" src=\"data:image/png;base64,([^\"]+)\">");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), img); it != std::sregex_iterator(); ++it)
    out.push_back({std::stoi((*it)[2]), (*it)[1], base64_decode((*it)[3])});
  return out;
}

std::size_t count_code(const std::string& pgm, char code) {
  const std::size_t header = pgm.find("255\n") + 4;
  return static_cast<std::size_t>(std::count(pgm.begin() + static_cast<std::ptrdiff_t>(header), pgm.end(), code));
}

// Every control point's thumbnail is the --png of `cmr region --point K` on
// its default plane (byte for byte, so pixel for pixel), and the report's
// plane, view and label counts are that command's (its --labels map counted).
void expect_thumbnails_are_regions(const std::string& file, int points, int size) {
  const std::string dir = (test::scratch() / "space_thumbs").string();
  const test::Outcome r =  // --fix-budget 0: every thumbnail, however loaded the machine (the budget's own test is below)
      run("report " + file + " --out " + dir + " --region-size " + std::to_string(size) + " --fix-budget 0");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(test::slurp(dir + "/report.json"));
  const int depth = doc["depth"];
  EXPECT_EQ(doc["region_size"], size);
  const auto& regions = doc["splines"][0]["regions"];
  const std::vector<Thumb> thumbs = thumbnails(test::slurp(dir + "/index.html"));
  ASSERT_EQ(thumbs.size(), static_cast<std::size_t>(points));
  ASSERT_EQ(regions.size(), static_cast<std::size_t>(points));
  for (int k = 0; k < points; ++k) {
    SCOPED_TRACE(testing::Message() << "P" << k);
    EXPECT_EQ(thumbs[k].point, k);
    EXPECT_NE(thumbs[k].alt.find("in the plane through P" + std::to_string(k) + " spanned by P"), std::string::npos)
        << thumbs[k].alt;
    const std::string png = (test::scratch() / "space_thumb_region.png").string();
    const std::string pgm = (test::scratch() / "space_thumb_region.pgm").string();
    std::ostringstream command;  // (one stream: GCC 12 warns -Wrestrict on a long chain of string +)
    command << "region " << file << " --point " << k << " --size " << size << "x" << size << " --depth " << depth
            << " --png " << png << " --labels " << pgm;
    const test::Outcome g = run(command.str());
    ASSERT_EQ(g.code, 0) << g.err;
    const auto reg = nlohmann::json::parse(g.out);
    EXPECT_EQ(regions[k]["point"], k);
    EXPECT_EQ(regions[k]["plane"], reg["plane"]);
    EXPECT_EQ(regions[k]["view"], reg["view"]);
    EXPECT_EQ(regions[k]["counts"], reg["counts"]);
    EXPECT_TRUE(thumbs[k].png == test::slurp(png)) << "the thumbnail is not cmr region's picture";
    const std::string labels = test::slurp(pgm);
    EXPECT_EQ(count_code(labels, '\x01'), regions[k]["counts"]["increasing"].get<std::size_t>());
    EXPECT_EQ(count_code(labels, '\x02'), regions[k]["counts"]["decreasing"].get<std::size_t>());
  }
}

TEST(SpaceReportThumbnails, OnePerPointEqualToRegionOnTheDefaultPlane) {
  expect_thumbnails_are_regions(kSpace + "fig8b_lifted.json", 6, 40);
}

// The label maps themselves: the report's in-memory regions (report/
// space_report.hpp) against the --labels map of `cmr region --point K`.
TEST(SpaceReportThumbnails, LabelMapsEqualRegionLabels) {
  const std::string file = kSpace + "fig8b_lifted.json";
  report::SpaceReportOptions o;
  o.region_size = 24;
  const report::SpaceReport r = report::space_report(file, o);
  ASSERT_TRUE(r.error.empty()) << r.error;
  ASSERT_EQ(r.thumbnails.size(), 6u);
  for (const report::SpaceThumbnail& t : r.thumbnails) {
    SCOPED_TRACE(testing::Message() << "P" << t.point);
    ASSERT_TRUE(t.error.empty()) << t.error;
    const std::string pgm = (test::scratch() / "space_thumb_labels.pgm").string();
    std::ostringstream command;
    command << "region " << file << " --point " << t.point << " --size 24x24 --depth " << o.max_depth << " --labels "
            << pgm;
    const test::Outcome g = run(command.str());
    ASSERT_EQ(g.code, 0) << g.err;
    const std::string labels = test::slurp(pgm);
    const std::string header = "P5\n24 24\n255\n";
    ASSERT_EQ(labels.substr(0, header.size()), header);
    const std::vector<std::uint8_t> codes = t.image.codes();
    EXPECT_EQ(std::string(codes.begin(), codes.end()), labels.substr(header.size()));
  }
}

TEST(SpaceReportThumbnails, RationalCurveToo) { expect_thumbnails_are_regions(kSpace + "fig8b_lifted_rational.json", 6, 16); }

// A point whose default plane is degenerate (its neighbours collinear with
// it) gets no thumbnail but the line `cmr region --point K` exits 2 with; the
// report is still written, and the other points get theirs.
TEST(SpaceReportThumbnails, DegenerateDefaultPlaneIsNamedNotFatal) {
  const std::string file = write("straight_start.json", R"({"points":[[0,0,0],[1,0,0],[2,0,0],[3,1,1],[4,1,3]]})");
  const std::string dir = (test::scratch() / "space_thumbs_degenerate").string();
  const test::Outcome r = run("report " + file + " --out " + dir + " --region-size 12 --fix-budget 0");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto regions = nlohmann::json::parse(test::slurp(dir + "/report.json"))["splines"][0]["regions"];
  ASSERT_EQ(regions.size(), 5u);
  const test::Outcome g = run("region " + file + " --point 1");
  EXPECT_EQ(g.code, 2);
  ASSERT_TRUE(regions[1].contains("error"));
  const std::string error = regions[1]["error"];
  EXPECT_NE(g.err.find(error), std::string::npos) << g.err << " vs " << error;
  EXPECT_FALSE(regions[1].contains("plane"));
  EXPECT_TRUE(regions[3].contains("plane"));
  const std::string html = test::slurp(dir + "/index.html");
  EXPECT_NE(html.find("P1: no region: "), std::string::npos);
  const std::vector<Thumb> thumbs = thumbnails(html);
  EXPECT_EQ(thumbs.size(), 3u);  // P0 and P1: collinear neighbours
}

// The default view (report::fit_space_view, issue 40 item 6) is the region
// and the moved point with a margin: for every point of the lifted Fig. 8b
// curve whose region shows, it fills at least a tenth of the picture (P2's
// was 215 of 102,400 pixels in the polygon's view), the point lies inside
// the view, and the labels are those of `cmr region --view` with that view.
// The summary's plane_name (the legend's last line) names the plane's axes.
TEST(SpaceReportThumbnails, DefaultViewIsTheRegionAndThePointWithAMargin) {
  const std::string file = kSpace + "fig8b_lifted.json";
  const std::string pgm = (test::scratch() / "space_fit.pgm").string(), pgm2 = (test::scratch() / "space_fit2.pgm").string();
  int shown = 0;
  for (int k = 1; k <= 4; ++k) {
    SCOPED_TRACE(testing::Message() << "P" << k);
    const test::Outcome g = run("region " + file + " --point " + std::to_string(k) + " --size 48x48 --labels " + pgm);
    ASSERT_EQ(g.code, 0) << g.err;
    const auto doc = nlohmann::json::parse(g.out);
    EXPECT_EQ(doc["view_fitted"], true);
    // The legend's last line names the plane and its axes (report::space_plane_name).
    std::ostringstream name;  // (one stream: GCC 12 warns -Wrestrict on a chain of string +)
    name << "plane through P" << k << ": a (right) along P" << k + 1 << " - P" << k << ", b (up) along P" << k - 1
         << " - P" << k;
    EXPECT_EQ(doc["plane_name"], name.str());
    const std::size_t region = doc["counts"]["increasing"].get<std::size_t>() + doc["counts"]["decreasing"].get<std::size_t>();
    if (region == 0) continue;
    ++shown;
    EXPECT_GE(region * 10, 48u * 48u) << g.out;
    // The moved point in plane coordinates (the default plane passes through it: its origin).
    const auto& plane = doc["plane"];
    const auto& v = doc["view"];
    const nlohmann::json points = nlohmann::json::parse(test::slurp(file))["points"];
    double q[3], u[3], w[3];
    for (int i = 0; i < 3; ++i)
      q[i] = points[k][i].get<double>() - plane["origin"][i].get<double>(), u[i] = plane["u"][i], w[i] = plane["v"][i];
    const auto dot = [](const double* x, const double* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    const double uu = dot(u, u), uv = dot(u, w), vv = dot(w, w), qu = dot(q, u), qv = dot(q, w);
    const double a = (qu * vv - qv * uv) / (uu * vv - uv * uv), b = (qv * uu - qu * uv) / (uu * vv - uv * uv);
    EXPECT_GT(a, v[0].get<double>());
    EXPECT_LT(a, v[2].get<double>());
    EXPECT_GT(b, v[1].get<double>());
    EXPECT_LT(b, v[3].get<double>());
    std::ostringstream again;
    again.precision(17);
    again << "region " << file << " --point " << k << " --size 48x48 --labels " << pgm2 << " --view " << v[0].get<double>()
          << "," << v[1].get<double>() << "," << v[2].get<double>() << "," << v[3].get<double>();
    const test::Outcome h = run(again.str());
    ASSERT_EQ(h.code, 0) << h.err;
    EXPECT_EQ(nlohmann::json::parse(h.out)["view_fitted"], false);
    EXPECT_TRUE(test::slurp(pgm) == test::slurp(pgm2)) << "the fitted view's labels are cmr region --view's";
  }
  EXPECT_GE(shown, 3);
}

TEST(SpaceReportThumbnails, NoThumbnailsLeavesThemOut) {
  const std::string dir = (test::scratch() / "space_thumbs_off").string();
  const test::Outcome r = run("report " + kSpace + "fig8b_lifted.json --out " + dir + " --no-thumbnails");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(test::slurp(dir + "/report.json"));
  EXPECT_FALSE(doc["splines"][0].contains("regions"));
  EXPECT_FALSE(doc.contains("region_size"));
  EXPECT_TRUE(thumbnails(test::slurp(dir + "/index.html")).empty());
}

}  // namespace
// The run's budget for fix searches and thumbnails (SpaceReportOptions::
// budget, `--fix-budget`; docs/space.md): what it leaves out is listed, never
// half drawn. A budget spent before anything starts leaves out every
// thumbnail and the failing curve's fix search; no budget (0) draws them all.
TEST(SpaceReportThumbnails, TheRunsBudgetListsWhatItLeavesOut) {
  const std::vector<std::string> files{kSpace + "fig8_lifted.json", kSpace + "fig8b_lifted.json"};
  report::SpaceReportOptions o;
  o.region_size = 16;
  const auto reports = [&](double budget) {
    o.budget = budget;
    std::vector<report::SpaceReport> rs;
    for (const std::string& f : files) rs.push_back(report::space_report_analysis(f, o));
    report::space_report_extras(rs, o);
    return rs;
  };
  const std::vector<report::SpaceReport> all = reports(0);
  ASSERT_FALSE(all[0].pass);  // fig8_lifted fails: it gets a fix search
  ASSERT_TRUE(all[0].fix.has_value());
  for (const report::SpaceReport& r : all) {
    EXPECT_EQ(static_cast<int>(r.thumbnails.size()), r.spline->unique_point_count());
    EXPECT_TRUE(r.regions_not_drawn.empty());
    EXPECT_FALSE(r.fix_not_searched);
  }
  const std::vector<report::SpaceReport> none = reports(1e-9);
  EXPECT_FALSE(none[0].fix.has_value());
  EXPECT_TRUE(none[0].fix_not_searched);
  for (const report::SpaceReport& r : none) {
    EXPECT_TRUE(r.thumbnails.empty());
    std::vector<int> every(static_cast<std::size_t>(r.spline->unique_point_count()));
    for (std::size_t k = 0; k < every.size(); ++k) every[k] = static_cast<int>(k);
    EXPECT_EQ(r.regions_not_drawn, every);
  }
  // The CLI: the note in report.json and on the page.
  const std::string dir = (test::scratch() / "space_thumbs_budget").string();
  const test::Outcome r = run("report " + files[0] + " --out " + dir + " --region-size 16 --fix-budget 0.000000001");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto spline = nlohmann::json::parse(test::slurp(dir + "/report.json"))["splines"][0];
  EXPECT_EQ(spline["regions"].size(), 0u);
  EXPECT_EQ(spline["regions_not_drawn"]["points"].size(), 6u);
  EXPECT_EQ(spline["regions_not_drawn"]["reason"],
            "the run's budget for fix searches and regions (--fix-budget 1e-09 s) was spent");
  EXPECT_EQ(spline["fix_not_searched"], spline["regions_not_drawn"]["reason"]);
  const std::string page = test::slurp(dir + "/index.html");
  EXPECT_NE(page.find("Not drawn: P0-P5 (the run&#39;s budget"), std::string::npos) << page.substr(0, 200);
  EXPECT_NE(page.find("No fix searched: the run"), std::string::npos);
}

}  // namespace cmr
