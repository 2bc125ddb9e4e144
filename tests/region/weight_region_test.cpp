// The region of a weight (region/weight_region.hpp, `cmr region --weight K`):
// the derivation's degrees in exact arithmetic, every reported interval and
// boundary against analyze() of the spline with that weight, the plot, and
// every bad-input line.
#include "region/weight_region.hpp"

#include <gtest/gtest.h>

#include <cairo.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bezierize/analyze.hpp"
#include "numeric/exact.hpp"
#include "bezierize/extract.hpp"
#include "bezierize/rational_lambda.hpp"
#include "region/region_setup.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tests/cli_util.hpp"

namespace cmr {
namespace {

using test::Outcome;
using test::run;
using test::scratch;
using test::write;
namespace fs = std::filesystem;

const std::string kSource = CMR_SOURCE_DIR;
const std::string kFig9b = kSource + "/examples/figures/fig9b.json";

// A quarter of the unit circle as a rational quadratic with weights (1, w, 1):
// the circle at w = sqrt(2)/2, an ellipse below, a hyperbola above.
const std::string kQuarterCircle = R"({"points": [[1, 0], [1, 1], [0, 1]], "weights": [1, 0.7071067811865476, 1]})";

/// The label analyze() gives the spline with w_K = w, read directly from its
/// fields (the independent check of region_label_code): cmrwi, Algorithm 2's
/// cmr, or the split verdict (cmrwi mode).
std::string analyze_label(const BSpline& s, int k, double w, Mode mode, std::optional<int> split = {}) {
  AnalyzeOptions ao;
  ao.split = split;
  ao.split_mode = mode;
  const SplineAnalysis a = analyze(with_weight(s, k, w), ao);
  if (split) return to_string(static_cast<Split>(code(*a.split)));
  return to_string(static_cast<Direction>(code(mode == Mode::cmr ? a.cmr_algorithm2 : a.cmrwi)));
}

nlohmann::json parse(const std::string& text) { return nlohmann::json::parse(text); }

/// Checks a reported weight region against analyze(): `inside` weights
/// spread over each interval (its ends included) have its label, each
/// boundary bracket is at most 1e-9 of the interval wide and analyze gives
/// the two labels at its ends, and the intervals tile [A, B] in order.
/// Returns how many label changes there are.
int check_against_analyze(const BSpline& s, const nlohmann::json& doc, Mode mode, std::optional<int> split = {},
                          int inside = 6) {
  const int k = doc["weight"];
  const double A = doc["from"], B = doc["to"];
  const nlohmann::json& iv = doc["intervals"];
  EXPECT_GE(iv.size(), 1u);
  EXPECT_EQ(iv.front()["from"].get<double>(), A);
  EXPECT_EQ(iv.back()["to"].get<double>(), B);
  for (std::size_t i = 0; i < iv.size(); ++i) {
    const double lo = iv[i]["from"], hi = iv[i]["to"];
    const std::string label = iv[i]["label"];
    EXPECT_LE(lo, hi) << "interval " << i;
    for (int j = 0; j <= inside; ++j) {
      const double w = j == inside ? hi : lo + (hi - lo) * j / inside;
      EXPECT_EQ(analyze_label(s, k, w, mode, split), label) << "interval " << i << " [" << lo << ", " << hi
                                                             << "], w = " << w;
    }
    if (i + 1 < iv.size()) {
      const double next = iv[i + 1]["from"];
      EXPECT_GT(next, hi) << "boundary " << i;
      EXPECT_LE(next - hi, 1e-9 * (B - A)) << "boundary " << i << " bracket [" << hi << ", " << next << "]";
      EXPECT_TRUE(iv[i + 1]["label"] != iv[i]["label"] || iv[i + 1]["pole"] != iv[i]["pole"]) << "boundary " << i;
    }
  }
  return static_cast<int>(iv.size()) - 1;
}

// The derivation of the header: with the other weights fixed, D's Bernstein
// coefficients are affine in w_K and lambda's polynomials of degree 4. In
// exact arithmetic, over six equally spaced weights, the second differences
// of D's coefficients and the fifth differences of lambda's vanish, and some
// fourth difference of lambda does not (the degree 4 is reached).
TEST(WeightRegion, DIsAffineAndLambdaQuarticInTheWeight) {
  const BSpline base = read_spline_file(kFig9b);
  for (int k = 0; k < base.point_count(); ++k) {
    std::vector<std::vector<Bernstein<Rational>>> lam, dee;  // per segment, per weight
    for (int step = 0; step < 6; ++step) {
      const BSpline s = with_weight(base, k, 0.5 + 0.25 * step);  // exact doubles
      for (const Segment& seg : s.segments()) {
        if (static_cast<int>(lam.size()) <= seg.index) lam.resize(seg.index + 1), dee.resize(seg.index + 1);
        const auto H = segment_homogeneous_points<Rational>(s, seg);
        lam[seg.index].push_back(rational_lambda_bernstein<Rational>(H));
        dee[seg.index].push_back(rational_d_bernstein<Rational>(H));
      }
    }
    bool quartic = false;
    for (std::size_t seg = 0; seg < lam.size(); ++seg) {
      for (std::size_t c = 0; c < lam[seg][0].size(); ++c) {
        std::vector<Rational> v;
        for (int step = 0; step < 6; ++step) v.push_back(lam[seg][step][c]);
        const Rational d4 = v[0] - 4 * v[1] + 6 * v[2] - 4 * v[3] + v[4];
        const Rational d5 = v[5] - 5 * v[4] + 10 * v[3] - 10 * v[2] + 5 * v[1] - v[0];
        EXPECT_EQ(sgn(d5), 0) << "P" << k << " segment " << seg << " xi_" << c;
        quartic = quartic || sgn(d4) != 0;
      }
      for (std::size_t c = 0; c < dee[seg][0].size(); ++c) {
        const Rational d2 = dee[seg][0][c] - 2 * dee[seg][1][c] + dee[seg][2][c];
        EXPECT_EQ(sgn(d2), 0) << "P" << k << " segment " << seg << " D_" << c;
      }
    }
    EXPECT_TRUE(quartic) << "P" << k << ": lambda should reach degree 4 in the weight";
  }
}

// with_weight: the weight is set, the rest kept; a polynomial spline gets
// weights 1; weight 1 everywhere is the polynomial spline again.
TEST(WeightRegion, WithWeightSetsOneWeight) {
  const BSpline s = read_spline_file(kFig9b);
  ASSERT_FALSE(s.is_rational());
  const BSpline r = with_weight(s, 2, 1.5);
  ASSERT_TRUE(r.is_rational());
  for (int i = 0; i < s.point_count(); ++i) {
    EXPECT_EQ(r.weight(i), i == 2 ? 1.5 : 1.0) << i;
    EXPECT_EQ(r.points()[i], s.points()[i]) << i;
  }
  EXPECT_EQ(r.knots(), s.knots());
  EXPECT_FALSE(with_weight(r, 2, 1.0).is_rational());
  EXPECT_EQ(with_weight(s, 2, 0.0).weight(2), 0.0);  // a zero weight is allowed (it may make a pole)
  EXPECT_THROW((void)with_weight(BSpline::bezier({{0, 0}, {1, 1}, {2, 0}}, "", {0, 1, 0}), 1, 0.0), InputError);
  EXPECT_THROW((void)with_weight(s, 2, std::nan("")), InputError);
  EXPECT_THROW((void)with_weight(s, 99, 1.0), InputError);
  // A closed spline: an unrolled point and its twin are one point with one weight.
  const BSpline c =
      BSpline::make_closed(2, {0, 1, 2, 3, 4, 5}, {{1, 0}, {0.3, 1}, {-0.8, 0.6}, {-0.8, -0.6}, {0.3, -1}});
  const int m = c.unique_point_count();
  ASSERT_EQ(c.twin(1), m + 1);
  for (const int k : {1, m + 1}) {
    const BSpline r2 = with_weight(c, k, 2.5);
    EXPECT_TRUE(r2.closed());
    EXPECT_EQ(r2.weight(1), 2.5) << k;
    EXPECT_EQ(r2.weight(m + 1), 2.5) << k;
    EXPECT_EQ(r2.weight(0), 1.0) << k;
    EXPECT_EQ(r2.points(), c.points()) << k;
  }
}

// The quarter circle with weights (1, w, 1): symmetric about its bisector for
// every w, so its curvature has an extremum at t = 1/2 and no weight in
// [0.3, 2] (in double, none is exactly the circle) is monotone; the command
// reports one interval, and analyze agrees at weights throughout, in both
// modes.
TEST(WeightRegion, QuarterCircleWeightsAgreeWithAnalyze) {
  const std::string file = write("quarter_circle.json", kQuarterCircle);
  const BSpline s = read_spline_file(file);
  for (const std::string mode : {"cmrwi", "cmr"}) {
    const Outcome r = run("region " + file + " --weight 1 --from 0.3 --to 2 --mode " + mode);
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json doc = parse(r.out);
    EXPECT_EQ(doc["weight"], 1);
    EXPECT_EQ(doc["samples"], WeightRegionRequest{}.samples);
    EXPECT_EQ(doc["current"].get<double>(), 0.7071067811865476);
    check_against_analyze(s, doc, mode == "cmr" ? Mode::cmr : Mode::cmrwi, {}, 40);
    ASSERT_EQ(doc["intervals"].size(), 1u);
    EXPECT_EQ(doc["intervals"][0]["label"], "none");
  }
  // The end weight 1 is not symmetric: the end weight changes the picture, and
  // the intervals still agree with analyze.
  const Outcome end = run("region " + file + " --weight 0 --from 0.3 --to 3 --samples 65");
  ASSERT_EQ(end.code, 0) << end.err;
  check_against_analyze(s, parse(end.out), Mode::cmrwi);
}

// Weights through zero: the quarter circle's W(t) = (1-t)^2 + 2 w t (1-t) + t^2
// has W(1/2) = (1 + w) / 2 and is positive on [0, 1] for w > -1, so the arc
// has a pole exactly for w <= -1 (W = (1 - 2t)^2 touches 0 at w = -1). The
// region of w in [-3, 2] is a pole interval ending at -1 within the
// tolerance, then pole-free intervals; analyze agrees at weights throughout,
// and SegmentShape::pole on both sides of the boundary.
TEST(WeightRegion, PolesAreMarkedWhereWVanishes) {
  const std::string file = write("quarter_circle.json", kQuarterCircle);
  const BSpline s = read_spline_file(file);
  const Outcome r = run("region " + file + " --weight 1 --from -3 --to 2 --samples 64");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json doc = parse(r.out);
  check_against_analyze(s, doc, Mode::cmrwi, {}, 20);
  const nlohmann::json& iv = doc["intervals"];
  ASSERT_GE(iv.size(), 2u);
  EXPECT_TRUE(iv[0]["pole"].get<bool>());
  EXPECT_EQ(iv[0]["label"], "none");
  const double left = iv[0]["to"].get<double>(), right = iv[1]["from"].get<double>();
  EXPECT_LE(left, -1.0);
  EXPECT_GT(right, -1.0);
  EXPECT_LE(right - left, 1e-9 * 5 + 1e-15);
  for (std::size_t i = 1; i < iv.size(); ++i) EXPECT_FALSE(iv[i]["pole"].get<bool>()) << i;
  const auto has_pole = [&](double w) { return analyze(with_weight(s, 1, w)).shapes[0].pole; };
  EXPECT_TRUE(has_pole(left));
  EXPECT_TRUE(has_pole(-1.0));
  EXPECT_FALSE(has_pole(right));
  EXPECT_FALSE(has_pole(std::nextafter(-1.0, 0.0)));
  // The plot marks the pole stretch (hatched) and is written.
  const fs::path dir = fs::temp_directory_path() / ("cmr_weight_pole_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Outcome p = run("region " + file + " --weight 1 --from -3 --to 2 --plot " + (dir / "w.png").string());
  EXPECT_EQ(p.code, 0) << p.err;
  EXPECT_GT(fs::file_size(dir / "w.png"), 1000u);
  // Curves through infinity are cut, never drawn with non-finite numbers.
  const Outcome v = run("region " + file + " --weight 1 --from -3 --to 2 --plot " + (dir / "w.svg").string());
  ASSERT_EQ(v.code, 0) << v.err;
  std::ifstream in(dir / "w.svg");
  const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
  fs::remove_all(dir);
}

// A polynomial cubic (Fig. 9(b), all weights 1): the weight of P2 makes the
// curvature increasing between two weights (about 0.877 and 1.436) and not
// monotone outside; each boundary is certified by analyze on both sides, and
// a dense independent scan (analyze at 400 weights) finds no weight whose
// label differs from its interval's.
TEST(WeightRegion, PolynomialCubicChangesLabelWhereAnalyzeDoes) {
  const BSpline s = read_spline_file(kFig9b);
  const Outcome r = run("region " + kFig9b + " --weight 2 --from 0.25 --to 3");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json doc = parse(r.out);
  EXPECT_EQ(doc["current"].get<double>(), 1.0);
  EXPECT_GE(check_against_analyze(s, doc, Mode::cmrwi), 2);
  // The spline as given (w = 1) is in an increasing interval: analyze(spline) says so.
  EXPECT_EQ(analyze(s).cmrwi, Direction::increasing);
  bool found = false;
  for (const auto& iv : doc["intervals"])
    found = found || (iv["from"].get<double>() <= 1 && iv["to"].get<double>() >= 1 && iv["label"] == "increasing");
  EXPECT_TRUE(found) << doc.dump();
  const nlohmann::json& iv = doc["intervals"];
  for (int i = 0; i < 400; ++i) {
    const double w = 0.25 + 2.75 * (i + 0.5) / 400;
    for (const auto& v : iv)
      if (w >= v["from"].get<double>() && w <= v["to"].get<double>()) {
        EXPECT_EQ(analyze_label(s, 2, w, Mode::cmrwi), v["label"].get<std::string>()) << "w = " << w;
      }
  }
}

// Split labels and CMR mode through the library call, against analyze.
TEST(WeightRegion, SplitAndCmrLabelsAgreeWithAnalyze) {
  const BSpline s = read_spline_file(kSource + "/examples/rational/nurbs_cubic.json");
  WeightRegionRequest q;
  q.point = 3;
  q.from = 0.5;
  q.to = 2;
  q.samples = 33;
  q.labels.split = 2;
  const WeightRegion split = weight_region(s, q);
  nlohmann::json doc = {{"weight", q.point}, {"from", q.from}, {"to", q.to}, {"intervals", nlohmann::json::array()}};
  for (const WeightInterval& v : split.intervals)
    doc["intervals"].push_back({{"from", v.from}, {"to", v.to}, {"label", split.label_name(v.label)}});
  EXPECT_GE(check_against_analyze(s, doc, Mode::cmrwi, 2, 4), 1) << doc.dump();
  q.labels.split.reset();
  q.labels.mode = Mode::cmr;
  const WeightRegion cmr = weight_region(s, q);
  doc["intervals"] = nlohmann::json::array();
  for (const WeightInterval& v : cmr.intervals)
    doc["intervals"].push_back({{"from", v.from}, {"to", v.to}, {"label", cmr.label_name(v.label)}});
  check_against_analyze(s, doc, Mode::cmr, {}, 4);
  EXPECT_GT(cmr.evaluations, q.samples);
  // Several joints (alternating labels, CMRWI) against analyze's alternation.
  q.labels.mode = Mode::cmrwi;
  q.labels.splits = {1, 2};
  const WeightRegion alt = weight_region(s, q);
  EXPECT_TRUE(alt.kind.alternating);
  for (const WeightInterval& v : alt.intervals)
    for (const double w : {v.from, (v.from + v.to) / 2, v.to}) {
      AnalyzeOptions ao;
      ao.splits = {1, 2};
      const SplineAnalysis a = analyze(with_weight(s, q.point, w), ao);
      EXPECT_EQ(code(*a.alternation), v.label) << "w = " << w;
    }
}

struct Rgb {
  int r, g, b;
  bool operator==(const Rgb&) const = default;
};

std::vector<Rgb> read_png(const fs::path& p, int& w, int& h) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(p.c_str());
  std::vector<Rgb> out;
  w = h = 0;
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    w = cairo_image_surface_get_width(s);
    h = cairo_image_surface_get_height(s);
    const unsigned char* data = cairo_image_surface_get_data(s);
    for (int j = 0; j < h; ++j) {
      const auto* row = reinterpret_cast<const uint32_t*>(data + j * cairo_image_surface_get_stride(s));
      for (int i = 0; i < w; ++i)
        out.push_back({static_cast<int>(row[i] >> 16 & 255), static_cast<int>(row[i] >> 8 & 255),
                       static_cast<int>(row[i] & 255)});
    }
  }
  cairo_surface_destroy(s);
  return out;
}

// --plot and -o: the files are written (JSON to the file, nothing on
// stdout); the PNG shows the region colour of `increasing` (draw.hpp: red,
// (255, 102, 102)) exactly when an interval is increasing; the SVG is SVG.
TEST(WeightRegion, PlotAndJsonFiles) {
  const fs::path dir = scratch() / "weight_plot";
  fs::create_directories(dir);
  const Outcome r = run("region " + kFig9b + " --weight 2 --from 0.25 --to 3 --plot " + (dir / "w.png").string() +
                        " -o " + (dir / "w.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  std::ifstream in(dir / "w.json");
  const nlohmann::json doc = nlohmann::json::parse(in);
  EXPECT_GE(doc["intervals"].size(), 3u);
  int w = 0, h = 0;
  const std::vector<Rgb> px = read_png(dir / "w.png", w, h);
  EXPECT_EQ(w, 800);
  EXPECT_EQ(h, 520);
  EXPECT_GT(std::count(px.begin(), px.end(), Rgb{255, 102, 102}), 1000);
  const std::string circle = write("quarter_circle.json", kQuarterCircle);
  const Outcome c = run("region " + circle + " --weight 1 --from 0.3 --to 2 --plot " + (dir / "c.png").string());
  ASSERT_EQ(c.code, 0) << c.err;
  const std::vector<Rgb> cp = read_png(dir / "c.png", w, h);
  EXPECT_EQ(std::count(cp.begin(), cp.end(), Rgb{255, 102, 102}), 0) << "no increasing interval, no red";
  const Outcome svg = run("region " + kFig9b + " --weight 2 --from 0.25 --to 3 --plot " + (dir / "w.svg").string());
  ASSERT_EQ(svg.code, 0) << svg.err;
  EXPECT_NE(test::slurp(dir / "w.svg").find("<svg"), std::string::npos);
}

// Bad input: one line on stderr, exit 2, no file written.
TEST(WeightRegion, BadInputIsOneLineAndExitTwo) {
  const fs::path dir = scratch() / "weight_bad";
  fs::create_directories(dir);
  const std::string plot = (dir / "p.png").string();
  const std::string f = kFig9b;
  const struct {
    std::string args, says;
  } cases[] = {
      {"--weight 9 --from 0.5 --to 2", "outside 0..5"},
      {"--weight -1 --from 0.5 --to 2", "outside 0..5"},
      {"--weight 2 --from 2 --to 2", "must be smaller than --to"},
      {"--weight 2 --from 3 --to 2", "must be smaller than --to"},
      {"--weight 2 --from nan --to 2", "finite"},
      {"--weight 2 --from 0.5 --to inf", "finite"},
      {"--weight 2 --from 0.5 --to inf", "must be finite"},
      {"--weight 2 --point 2 --from 0.5 --to 2", "excludes"},
      {"--weight 2 --from 0.5 --to 2 --samples 1000000", "--samples: 1000000 is outside 2..100000"},
      {"--weight 2 --from 0.5 --to 2 --samples 1", "--samples: 1 is outside"},
      {"--weight 2 --from 0.5", "needs --from A and --to B"},
      {"--weight 2 --from 0.5 --to 2 --png x.png", "--png is for --point"},
      {"--weight 2 --from 0.5 --to 2 --backend cpu", "--backend is for --point"},
      {"--weight 2 --from 0.5 --to 2 --split 9", "split 9 is outside"},
      {"--weight 2 --from 0.5 --to 2 --plot " + (dir / "p.jpg").string(), "must end in .png or .svg"},
      {"--point 2 --from 0.5", "--from is for --weight"},
      {"--from 0.5 --to 2", "--point is required (see cmr region --help), or --weight K"},
  };
  for (const auto& c : cases) {
    const std::string args = c.args.find("--plot") == std::string::npos ? c.args + " --plot " + plot : c.args;
    const Outcome r = run("region " + f + " " + args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(r.out, "") << args;
    EXPECT_FALSE(fs::exists(plot)) << args;
  }
}

}  // namespace
}  // namespace cmr
