#include "tools/figures.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <iomanip>
#include <map>
#include <memory>
#include <sstream>
#include <system_error>

#include <nlohmann/json.hpp>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "bezierize/analyze.hpp"
#include "bezierize/extremum_terms.hpp"
#include "design/kcurve.hpp"
#include "bezierize/lambda.hpp"
#include "numeric/roots.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "draw/draw.hpp"
#include "io/output.hpp"

namespace cmr::fig {

namespace {

// ------------------------------------------------------------------ curves --
//
// The paper prints no coordinates. Each curve below was found by a search on
// region maps and analyze() (seeded random or hill-climbing over the free
// points, coordinates rounded to 0.01) so that the paper's statements about
// its figure hold; the claims re-check them on every run.

BSpline renamed(const BSpline& s, const std::string& name) {
  return BSpline::make(s.degree(), s.knots(), s.points(), name);
}
BSpline moved(const BSpline& s, int k, Vec2 p, const std::string& name) { return renamed(s.with_point(k, p), name); }

struct Curves {
  // Fig. 1: (a) a class A cubic (legs turning by 0.35 rad and growing by
  // 1.3, rounded to 0.01): every xi_i < 0, decreasing curvature decided at
  // level 0; (b) is Fig. 2(b) below, whose end coefficients have opposite
  // signs (not monotone, decided at level 0).
  BSpline fig1a = BSpline::bezier({{0, 0}, {1, 0}, {2.22, 0.45}, {3.51, 1.53}}, "fig1a");

  // Fig. 4: Fig. 1(a) with P3 bent up to (3.16, 2.24) (found by a seeded
  // search over single-point moves): not monotone, and every point has a CMR
  // in the default view. (b)-(e): each point moved to the centre of its CMR
  // (the region pixel nearest the region's centroid, rounded to 0.01).
  BSpline fig4 = BSpline::bezier({{0, 0}, {1, 0}, {2.22, 0.45}, {3.16, 2.24}}, "fig4");
  Vec2 fig4_place[4] = {{0.48, 0.14}, {0.72, -0.19}, {2.22, 0.87}, {3.53, 1.45}};
  BSpline fig4x[4] = {moved(fig4, 0, fig4_place[0], "fig4b"), moved(fig4, 1, fig4_place[1], "fig4c"),
                      moved(fig4, 2, fig4_place[2], "fig4d"), moved(fig4, 3, fig4_place[3], "fig4e")};

  // Figs. 2, 3, 7: a flat cubic arch whose P0 has a blue CMRWI next to P0 and
  // a red one below it, where the curve gets an inflection.
  BSpline fig2 = BSpline::bezier({{0, 0}, {0.3, -0.5}, {1.6, -0.3}, {3, 0}}, "fig2");
  Vec2 fig2_place[4] = {{-0.5, -0.3}, {0, 0.5}, {-0.5, -1.0}, {1, -1}};  // (a) blue, (b) out, (c) red, (d) out
  BSpline fig2x[4] = {moved(fig2, 0, fig2_place[0], "fig2a"), moved(fig2, 0, fig2_place[1], "fig2b"),
                      moved(fig2, 0, fig2_place[2], "fig2c"), moved(fig2, 0, fig2_place[3], "fig2d")};

  // Fig. 5: P2 left of P1 gives a sharp kink (nearly a cusp) that no single
  // point can smooth out; pulling P1 right opens a small blue CMR for P2.
  BSpline fig5 = BSpline::bezier({{0, 0}, {0.7, 1.4}, {-0.6, 0.8}, {3, 0}}, "fig5");
  BSpline fig5c = moved(fig5, 1, {1.5, 1.0}, "fig5c");
  BSpline fig5d = moved(fig5c, 2, {2.7, 0.5}, "fig5d");

  // Fig. 6: a class A quintic (legs turning by 0.35 rad and growing by 1.15,
  // so its curvature decreases) with P5 pulled in to (3.6, 4.3), which makes
  // the curvature non-monotone; P5 moved out to (4, 5) restores it.
  BSpline fig6 =
      BSpline::bezier({{0, 0}, {1, 0}, {2.08, 0.39}, {3.09, 1.24}, {3.85, 2.56}, {3.6, 4.3}}, "fig6");
  BSpline fig6c = moved(fig6, 5, {4, 5}, "fig6c");

  // Fig. 8: a clockwise spiral polygon (turning -0.8 rad, legs x1.6) with
  // every point then hill-climbed so that the CMRs of P1, P2, P3 are as large
  // as possible while P0, P4, P5 have none: both of the first two segments
  // are off, which only a point acting on both can repair.
  BSpline fig8 = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7},
                               {{1.30, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95},
                                {-6.78, -9.78}},
                               "fig8");
  BSpline fig8b = moved(fig8, 3, {1.2, -4.03}, "fig8b");

  // Fig. 9: the clockwise class A cubic (turning -0.5 rad, legs x2.5) written
  // on the clamped knots, whose curvature increases, with P3 pulled in to
  // (1.5, -1); (b) puts P3 back where the polynomial had it.
  BSpline fig9 = BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3},
                               {{0, 0}, {0.33, 0}, {1.27, -0.27}, {1.5, -1.0}, {5.45, -4.7}, {6.57, -6.46}}, "fig9");
  BSpline fig9b = moved(fig9, 3, {3.46, -2.1}, "fig9b");

  // Fig. 10: from Fig. 9(b), P5 (which shapes the last span only) bent
  // inwards makes that span decreasing: a maximum at the joint u = 2; moved
  // along the spiral it stays increasing.
  BSpline fig10a = moved(fig9b, 5, {5.4, -5.8}, "fig10a");
  BSpline fig10b = moved(fig9b, 5, {6.5, -6.3}, "fig10b");

  // Fig. 11: two cubic Bezier pieces Q1..Q4 and Q4..Q7 (indices 0..6, knots
  // of multiplicity 3 at the joint) with G1 at Q4 (Q3, Q4, Q5 on one line).
  // Chosen by hand so that each piece is monotone, then Q3, Q4, Q5 moved
  // together by (-0.5, 0.5) (rigidly: G1 stays exact), which makes both
  // pieces non-monotone; Q4's each-piece region holds the way back.
  BSpline fig11 = BSpline::make(3, {0, 0, 0, 1, 1, 1, 2, 2, 2},
                                {{0, 0}, {1, 0}, {1.5, 0.9}, {2.5, 1.7}, {3.3, 2.34}, {4.2, 2.9}, {4.2, 4}}, "fig11");
};

View square_view(double cx, double cy, double half) { return {cx - half, cy - half, cx + half, cy + half}; }

// ----------------------------------------------------------------- helpers --

/// Pixels whose label code (cmr::code) is `label`: the claims below name
/// labels by their codes, as the README documents them.
long count(const RegionResult& r, uint8_t label) {
  long n = 0;
  for (std::size_t i = 0; i < r.size(); ++i) n += r.code_at(i) == label;
  return n;
}

/// The label code of the pixel containing p; 255 outside the image.
uint8_t label_at(const RegionResult& r, Vec2 p) {
  const View& v = r.view;
  const double fi = (p.x - v.x0) / (v.x1 - v.x0) * r.width, fj = (v.y1 - p.y) / (v.y1 - v.y0) * r.height;
  if (!(fi >= 0 && fi < r.width && fj >= 0 && fj < r.height)) return 255;
  return r.code_at(static_cast<std::size_t>(fj) * r.width + static_cast<std::size_t>(fi));
}

std::string counts(const RegionResult& r) {
  return "red " + std::to_string(count(r, 1)) + ", blue " + std::to_string(count(r, 2)) + ", undecided " +
         std::to_string(count(r, 3)) + " of " + std::to_string(r.size()) + " px";
}

std::string split_counts(const RegionResult& r) {
  static const char* names[] = {"none", "inc-inc", "inc-dec", "dec-inc", "dec-dec", "undecided"};
  std::string s;
  for (uint8_t l = 0; l <= 5; ++l) s += (l ? ", " : "") + std::string(names[l]) + " " + std::to_string(count(r, l));
  return s + " px";
}

/// Pixels of `inner` that are coloured but not the same colour in `outer`.
long outside(const RegionResult& inner, const RegionResult& outer) {
  long n = 0;
  for (std::size_t i = 0; i < inner.labels.size(); ++i)
    n += (inner.labels[i] == Direction::increasing || inner.labels[i] == Direction::decreasing) &&
         inner.labels[i] != outer.labels[i];
  return n;
}

bool has_inflection(const SplineAnalysis& a) {
  for (const SegmentClass& c : a.segments)
    if (c.inflection.inflection == Inflection::present) return true;
  return false;
}

std::string point_text(Vec2 p) {
  std::ostringstream s;
  s << '(' << p.x << ", " << p.y << ')';
  return s.str();
}

std::string label_text(uint8_t l) { return l == 255 ? "outside the view" : "label " + std::to_string(l); }

// ----------------------------------------------------------------- builder --

/// Computes and caches regions and analyses, records claims, stages files
/// (make_figures commits them together at the end).
class Builder {
 public:
  Builder(const FiguresOptions& o, OutputSet& out) : options_(o), out_(out) {}

  /// The region of point k of s; cached by (name, k, mode, split, depth),
  /// so figures that show the same map share it.
  const RegionResult& region(const BSpline& s, int k, Mode mode, const View& view, std::optional<int> split = {},
                            std::optional<int> depth = {}) {
    RegionRequest ro;
    ro.point = k;
    ro.mode = mode;
    ro.split = split;
    ro.max_depth = depth.value_or(options_.depth);
    ro.width = ro.height = options_.size;
    ro.view = view;
    std::ostringstream key;
    key << s.name() << '|' << k << '|' << static_cast<int>(mode) << '|' << split.value_or(0) << '|' << ro.max_depth;
    auto it = regions_.find(key.str());
    if (it != regions_.end()) return it->second;
    const auto t0 = std::chrono::steady_clock::now();
    CMR_CHECK(options_.backend != nullptr);
    RegionResult image = options_.backend->render(RegionProblem::make(s, ro));
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ostringstream line;
    line << "  " << s.name() << ": P" << k << ' ' << (mode == Mode::cmr ? "CMR" : "CMRWI");
    if (split) line << " split " << *split;
    if (depth) line << " depth " << *depth;
    line << " (" << ro.width << 'x' << ro.height << ", " << std::fixed << std::setprecision(3) << dt << " s)";
    log(line.str());
    return regions_.emplace(key.str(), std::move(image)).first->second;
  }

  const SplineAnalysis& analysis(const BSpline& s, std::optional<int> split = {}) {
    const std::string key = s.name() + '|' + std::to_string(split.value_or(0));
    auto it = analyses_.find(key);
    if (it != analyses_.end()) return it->second;
    AnalyzeOptions ao;
    ao.classify.max_depth = options_.depth;
    ao.split = split;
    ao.split_mode = Mode::cmr;
    return analyses_.emplace(key, analyze(s, ao)).first->second;
  }

  void claim(const std::string& figure, const std::string& text, bool pass, const std::string& detail) {
    result_.claims.push_back({figure, text, pass, detail});
  }

  /// Writes the figure as id.png and id.svg and records its title and
  /// caption for the page. The texts are copied from `figure` here, in one
  /// place: the figure is passed by value, so reading them in the caller's
  /// argument list (as this once did) could see them already moved out. The
  /// legend is that of every region panel (legend_for: the colours drawn).
  void write(const std::string& id, draw::Figure figure) {
    figure.panel_size = options_.size;
    figure.legend.clear();
    for (const auto& row : figure.rows)
      for (const draw::Panel& p : row)
        if (const auto* pic = std::get_if<draw::RegionPicture>(&p.content))
          for (const draw::LegendEntry& e : draw::legend_for(*pic))
            if (std::none_of(figure.legend.begin(), figure.legend.end(),
                             [&](const draw::LegendEntry& o) { return o.text == e.text; }))
              figure.legend.push_back(e);
    // White (not monotone) last, whichever panel listed it first.
    std::stable_partition(figure.legend.begin(), figure.legend.end(), [](const draw::LegendEntry& e) {
      return e.ring || e.colour.r < 1 || e.colour.g < 1 || e.colour.b < 1;
    });
    FigureFile file{id, figure.title, figure.caption, {}, {}};
    for (const auto& row : figure.rows)
      for (const draw::Panel& p : row) file.panels.push_back(p.label);
    const std::filesystem::path png = options_.out / (id + ".png"), svg = options_.out / (id + ".svg");
    out_.stage(png, draw::figure_png(figure, &file.labels));
    out_.stage(svg, draw::figure_svg(figure));
    result_.written.push_back(png);
    result_.written.push_back(svg);
    log("made " + png.string() + " and .svg");
    result_.figures.push_back(std::move(file));
  }

  void log(const std::string& line) const {
    if (options_.progress) *options_.progress << line << std::endl;
  }

  const FiguresOptions& options() const { return options_; }
  OutputSet& out() { return out_; }
  FiguresResult& result() { return result_; }
  /// Keeps an image alive until the figures are written (pictures point to it).
  void keep(std::shared_ptr<const RegionResult> image) { kept_.push_back(std::move(image)); }

 private:
  const FiguresOptions& options_;
  OutputSet& out_;
  std::map<std::string, RegionResult> regions_;  // node-based: references stay valid
  std::map<std::string, SplineAnalysis> analyses_;
  std::vector<std::shared_ptr<const RegionResult>> kept_;
  FiguresResult result_;
};

draw::RegionPicture picture(const BSpline& s, std::vector<const RegionResult*> layers, int max_depth) {
  draw::RegionPicture p;
  p.spline = &s;
  p.layers = std::move(layers);
  p.max_depth = max_depth;
  return p;
}

draw::RegionPicture moved_picture(const BSpline& s, const RegionResult& layer, Vec2 from, int k, int max_depth) {
  draw::RegionPicture p = picture(s, {&layer}, max_depth);
  p.moved = std::make_pair(from, s.points()[k]);
  return p;
}

/// The CMRWIs (or CMRs) of every point of s, one layer each.
std::vector<const RegionResult*> all_points(Builder& b, const BSpline& s, Mode mode, const View& v) {
  std::vector<const RegionResult*> layers;
  for (int k = 0; k < s.point_count(); ++k) layers.push_back(&b.region(s, k, mode, v));
  return layers;
}

// ----------------------------------------------------------------- figures --

/// A region layer with no region: pictures of a curve alone (Figs. 1, 13).
const RegionResult& blank_layer(Builder& b, const View& view) {
  const int size = b.options().size;
  auto blank = std::make_shared<RegionResult>(RegionResult::blank(size, size, view));
  b.keep(blank);
  return *blank;
}

/// lambda's Bernstein coefficients (Eq. 4) of a Bezier curve, in double.
std::vector<double> xi_of(const BSpline& s) {
  std::vector<Point<double>> P;
  for (const Vec2& p : s.points()) P.push_back(to_point<double>(p));
  return lambda_bernstein<double>(P);
}

/// Fig. 1 (section 3): lambda of a monotone and of a non-monotone cubic.
void figure1(Builder& b, const Curves& c) {
  const BSpline& mono = c.fig1a;
  const BSpline& non = c.fig2x[1];
  const int depth = b.options().depth;
  draw::Figure f;
  f.title = "Fig. 1: cubic Bezier curves and their lambda(t)";
  for (const BSpline* s : {&mono, &non}) {
    const bool first = s == &mono;
    const std::vector<double> xi = xi_of(*s);
    const SplineAnalysis& a = b.analysis(*s);
    const SegmentClass& sc = a.segments[0];
    // lambda sampled from the derivatives (curvature_at) must have the signs
    // of the Bernstein form wherever it is clearly away from zero.
    int sign_mismatch = 0;
    double largest = 0;
    for (double x : xi) largest = std::max(largest, std::abs(x));
    for (int k = 0; k <= 100; ++k) {
      const double t = k / 100.0;
      std::vector<double> w = xi;
      for (std::size_t r = 1; r < w.size(); ++r)
        for (std::size_t i = 0; i + r < w.size(); ++i) w[i] = (1 - t) * w[i] + t * w[i + 1];
      const double direct = curvature_at(*s, t).lambda;
      if (std::abs(w[0]) > 1e-6 * largest && (direct > 0) != (w[0] > 0)) ++sign_mismatch;
    }
    std::ostringstream xs;
    for (std::size_t i = 0; i < xi.size(); ++i) xs << (i ? ", " : "") << std::setprecision(3) << xi[i];
    if (first) {
      const bool all_negative = std::all_of(xi.begin(), xi.end(), [](double x) { return x < 0; });
      b.claim("Fig. 1a", "every xi_i is negative: decreasing curvature, decided without subdivision",
              all_negative && a.cmrwi == Direction::decreasing && sc.monotonicity.depth == 0,
              "xi = (" + xs.str() + "), analyze " + to_string(a.cmrwi) + " at level " +
                  std::to_string(sc.monotonicity.depth));
    } else {
      b.claim("Fig. 1b", "xi_0 xi_5 < 0: not monotone, decided without subdivision",
              xi.front() * xi.back() < 0 && a.cmrwi == Direction::none && sc.monotonicity.depth == 0,
              "xi = (" + xs.str() + "), analyze " + to_string(a.cmrwi) + " at level " +
                  std::to_string(sc.monotonicity.depth));
    }
    b.claim(first ? "Fig. 1a" : "Fig. 1b", "lambda from the derivatives has the signs of its Bernstein form",
            sign_mismatch == 0, std::to_string(sign_mismatch) + " of 101 samples differ in sign");
    const View v = default_view(*s, b.options().size, b.options().size);
    const std::string id = first ? "(a)" : "(b)";
    f.rows.push_back({{picture(*s, {&blank_layer(b, v)}, depth), id + (first ? " monotone (decreasing) curvature"
                                                                                   : " non-monotone curvature")},
                      {draw::LambdaPlot{xi}, "lambda(t) of " + id + "; dots: xi_0..xi_5"},
                      {draw::CurvaturePlot{s, &a}, "curvature plot of " + id}});
  }
  f.caption = "lambda is the numerator of dkappa/ds (Eq. 3); its Bernstein coefficients xi_0..xi_5 (Eq. 4) bound it. "
              "(a) The class A cubic (0,0), (1,0), (2.22,0.45), (3.51,1.53): all xi_i < 0, so the curvature "
              "decreases (condition (2) of Algorithm 1 at level 0). (b) The cubic of Fig. 2(b): xi_0 > 0 > xi_5, so "
              "lambda changes sign and the curvature is not monotone, decided at once.";
  b.write("fig1", std::move(f));
}

void figure2(Builder& b, const Curves& c) {
  const View v = square_view(0.9, -0.8, 2.8);
  const RegionResult& r = b.region(c.fig2, 0, Mode::cmrwi, v);
  b.claim("Fig. 2", "P0's CMRWI has a blue and a red part", count(r, 1) > 0 && count(r, 2) > 0, counts(r));
  struct Case {
    const char* id;
    uint8_t label;
    Direction verdict;
    const char* text;
  };
  const Case cases[4] = {
      {"a", 2, Direction::decreasing, "P0 in the blue region: the curvature decreases"},
      {"b", 0, Direction::none, "P0 outside the regions: the curvature is not monotone"},
      {"c", 1, Direction::increasing, "P0 in the red region: the curvature increases, with an inflection"},
      {"d", 0, Direction::none, "P0 outside the regions: the curvature is not monotone"},
  };
  const int depth = b.options().depth;
  draw::Figure f;
  f.title = "Fig. 2: CMRWIs of P0 of a cubic Bezier curve and four placements of P0";
  for (int i = 0; i < 4; ++i) {
    const Case& k = cases[i];
    const BSpline& s = c.fig2x[i];
    const SplineAnalysis& a = b.analysis(s);
    const uint8_t l = label_at(r, c.fig2_place[i]);
    bool pass = l == k.label && a.cmrwi == k.verdict;
    std::string detail = "P0 at " + point_text(c.fig2_place[i]) + ": " + label_text(l) + ", analyze cmrwi " +
                         to_string(a.cmrwi);
    if (k.id[0] == 'c') {
      pass = pass && has_inflection(a);
      detail += has_inflection(a) ? ", inflection present" : ", no inflection";
    }
    b.claim(std::string("Fig. 2") + k.id, k.text, pass, detail);
    if (i % 2 == 0) f.rows.emplace_back();
    f.rows.back().push_back(
        {moved_picture(s, r, c.fig2.points()[0], 0, depth), std::string("(") + k.id + ") " + k.text});
    f.rows.back().push_back({draw::CurvaturePlot{&s, &a}, std::string("curvature plot of (") + k.id + ")"});
  }
  f.caption = "The CMRWI of P0 (where P0 may go so that the curvature is monotone, inflections allowed) of the "
              "cubic (0,0), (0.3,-0.5), (1.6,-0.3), (3,0); the hollow circle is P0's original place. A flat arch "
              "was chosen because its P0 has both a blue region beside it and a red one below, where the curve "
              "turns the other way first (an inflection).";
  b.write("fig2", std::move(f));
}

void figure3(Builder& b, const Curves& c) {
  const View v = square_view(0.9, -0.8, 2.8);
  const auto wi = all_points(b, c.fig2, Mode::cmrwi, v);
  const auto cmr = all_points(b, c.fig2, Mode::cmr, v);
  std::string sizes;
  bool every = true, inside = true;
  long out_total = 0, wi_area = 0, cmr_area = 0;
  for (int k = 0; k < 4; ++k) {
    const long n = count(*wi[k], 1) + count(*wi[k], 2);
    every = every && n > 0;
    sizes += (k ? "; P" : "P") + std::to_string(k) + " " + counts(*wi[k]);
    const long o = outside(*cmr[k], *wi[k]);
    inside = inside && o == 0;
    out_total += o;
    wi_area += n;
    cmr_area += count(*cmr[k], 1) + count(*cmr[k], 2);
  }
  b.claim("Fig. 3", "every control point of the cubic has a non-empty CMRWI", every, sizes);
  b.claim("Fig. 3", "each point's CMR lies inside its CMRWI, in the same colour", inside,
          std::to_string(out_total) + " CMR px outside");
  b.claim("Fig. 3", "the CMRs are smaller than the CMRWIs (positions with an inflection drop out)",
          cmr_area < wi_area, "CMR " + std::to_string(cmr_area) + " px, CMRWI " + std::to_string(wi_area) + " px");
  const int depth = b.options().depth;
  draw::Figure f;
  f.title = "Fig. 3: CMRWIs and CMRs of all control points of a cubic Bezier curve";
  f.rows.push_back({{picture(c.fig2, wi, depth), "(a) CMRWIs of P0..P3, overlapped"},
                    {picture(c.fig2, cmr, depth), "(b) CMRs of P0..P3, overlapped"},
                    {draw::CurvaturePlot{&c.fig2, &b.analysis(c.fig2)}, "(c) curvature plot"}});
  f.caption = "Each point's region is computed with the other points fixed; where regions overlap their colours "
              "are subtracted from white once per region, so overlaps are darker. Same cubic as Fig. 2.";
  b.write("fig3", std::move(f));
}

/// Fig. 4: CMRs of every point of a non-monotone cubic, and each point
/// moved within its CMR to a curve with monotone curvature.
void figure4(Builder& b, const Curves& c) {
  const View v = default_view(c.fig4, b.options().size, b.options().size);
  const auto cmr = all_points(b, c.fig4, Mode::cmr, v);
  const SplineAnalysis& a = b.analysis(c.fig4);
  std::string sizes;
  bool every = true;
  for (int k = 0; k < 4; ++k) {
    every = every && count(*cmr[k], 1) + count(*cmr[k], 2) > 0;
    sizes += (k ? "; P" : "P") + std::to_string(k) + " " + counts(*cmr[k]);
  }
  b.claim("Fig. 4a", "the curvature is not monotone and every control point has a CMR", a.cmr == Direction::none && every,
          std::string("analyze cmr ") + to_string(a.cmr) + "; " + sizes);
  long overlap = 0;
  for (std::size_t i = 0; i < cmr[0]->size(); ++i) {
    int n = 0;
    for (const RegionResult* r : cmr) n += r->code_at(i) == 1 || r->code_at(i) == 2;
    overlap += n > 1;
  }
  b.claim("Fig. 4a", "CMRs of different points overlap (darker where they do)", overlap > 0,
          std::to_string(overlap) + " px in two or more CMRs");
  const int depth = b.options().depth;
  draw::Figure f;
  f.title = "Fig. 4: CMRs of all control points, and each point moved within its CMR";
  f.rows.push_back({{picture(c.fig4, cmr, depth), "(a) CMRs of P0..P3, overlapped: not monotone"},
                    {draw::CurvaturePlot{&c.fig4, &a}, "curvature plot of (a)"}});
  for (int k = 0; k < 4; ++k) {
    const BSpline& s = c.fig4x[k];
    const SplineAnalysis& ak = b.analysis(s);
    const uint8_t l = label_at(*cmr[k], c.fig4_place[k]);
    const std::string id(1, static_cast<char>('b' + k));
    b.claim("Fig. 4" + id, "P" + std::to_string(k) + " moved within its CMR: the curvature is monotone, no inflection",
            (l == 1 || l == 2) && ak.cmr != Direction::none && ak.cmr != Direction::undecided &&
                code(ak.cmr) == l,
            "P" + std::to_string(k) + " at " + point_text(c.fig4_place[k]) + ": " + label_text(l) + ", analyze cmr " +
                to_string(ak.cmr));
    if (k % 2 == 0) f.rows.emplace_back();
    f.rows.back().push_back({moved_picture(s, *cmr[k], c.fig4.points()[k], k, depth),
                             "(" + id + ") P" + std::to_string(k) + " moved within its CMR"});
    f.rows.back().push_back({draw::CurvaturePlot{&s, &ak}, "curvature plot of (" + id + "): " + to_string(ak.cmr)});
  }
  f.caption = "The cubic (0,0), (1,0), (2.22,0.45), (3.16,2.24) (Fig. 1(a) with P3 bent up, which makes the "
              "curvature non-monotone) and the CMR of each control point, the others fixed; overlapping CMRs are "
              "darker. (b)-(e): each point in turn moved to the middle of its CMR (hollow circle: its old place) "
              "gives monotonically varying curvature without an inflection.";
  b.write("fig4", std::move(f));
}

void figure5(Builder& b, const Curves& c) {
  const View v = square_view(1.0, 0.6, 2.6);
  const auto base = all_points(b, c.fig5, Mode::cmr, v);
  long any = 0;
  for (const RegionResult* r : base) any += count(*r, 1) + count(*r, 2);
  const SplineAnalysis& a = b.analysis(c.fig5);
  b.claim("Fig. 5a", "the curve is not monotone and no control point has a CMR in the view",
          any == 0 && a.cmr == Direction::none,
          std::to_string(any) + " region px over P0..P3, analyze cmr " + to_string(a.cmr));
  const auto after = all_points(b, c.fig5c, Mode::cmr, v);
  b.claim("Fig. 5c", "after moving P1, P2 has a (blue) CMR", count(*after[2], 2) > 0, "P2 " + counts(*after[2]));
  const SplineAnalysis& ad = b.analysis(c.fig5d);
  const Vec2 p2 = c.fig5d.points()[2];
  const uint8_t l = label_at(*after[2], p2);
  b.claim("Fig. 5d", "P2 moved into its blue region: the curvature decreases, no inflection",
          l == 2 && ad.cmr == Direction::decreasing,
          "P2 at " + point_text(p2) + ": " + label_text(l) + ", analyze cmr " + to_string(ad.cmr));
  const int depth = b.options().depth;
  draw::Figure f;
  f.title = "Fig. 5: a cubic Bezier curve with no CMRs, and moves that make its curvature monotone";
  f.rows.push_back({{picture(c.fig5, base, depth), "(a) CMRs of P0..P3: none in the view"},
                    {draw::CurvaturePlot{&c.fig5, &a}, "(b) curvature plot of (a)"}});
  draw::RegionPicture moved_p1 = picture(c.fig5c, after, depth);  // every point's CMR after the move
  moved_p1.moved = std::make_pair(c.fig5.points()[1], c.fig5c.points()[1]);
  f.rows.push_back({{moved_p1, "(c) P1 moved: CMRs appear"},
                    {moved_picture(c.fig5d, *after[2], c.fig5c.points()[2], 2, depth),
                     "(d) P2 moved into its blue CMR"},
                    {draw::CurvaturePlot{&c.fig5d, &ad}, "(e) curvature plot of (d): decreasing"}});
  f.caption = "The cubic (0,0), (0.7,1.4), (-0.6,0.8), (3,0) has a sharp kink, nearly a cusp, because P2 lies "
              "left of P1; no single point can smooth it out without an inflection or a second extremum. Moving P1 "
              "to (1.5,1) opens a small blue CMR for P2 near P3; P2 at (2.7,0.5) inside it gives decreasing "
              "curvature.";
  b.write("fig5", std::move(f));
}

void figure6(Builder& b, const Curves& c) {
  const View v = square_view(2.3, 2.6, 3.4);
  const auto wi = all_points(b, c.fig6, Mode::cmrwi, v);
  const auto cmr = all_points(b, c.fig6, Mode::cmr, v);
  const SplineAnalysis& a = b.analysis(c.fig6);
  b.claim("Fig. 6a", "the quintic's curvature is not monotone", a.cmrwi == Direction::none,
          std::string("analyze cmrwi ") + to_string(a.cmrwi));
  const long wi5 = count(*wi[5], 1) + count(*wi[5], 2), cmr5 = count(*cmr[5], 1) + count(*cmr[5], 2);
  const long out = outside(*cmr[5], *wi[5]);
  b.claim("Fig. 6a-b", "P5 has a blue CMR inside its larger CMRWI",
          count(*cmr[5], 2) > 0 && out == 0 && cmr5 < wi5,
          "CMRWI " + counts(*wi[5]) + "; CMR " + counts(*cmr[5]) + "; " + std::to_string(out) + " CMR px outside");
  const SplineAnalysis& ac = b.analysis(c.fig6c);
  const Vec2 p5 = c.fig6c.points()[5];
  const uint8_t l = label_at(*cmr[5], p5);
  b.claim("Fig. 6c", "P5 moved within its CMR: the curvature decreases, no inflection",
          l == 2 && ac.cmr == Direction::decreasing,
          "P5 at " + point_text(p5) + ": " + label_text(l) + ", analyze cmr " + to_string(ac.cmr));
  const int depth = b.options().depth;
  draw::Figure f;
  f.title = "Fig. 6: CMRWIs and CMRs of a quintic Bezier curve";
  f.rows.push_back({{picture(c.fig6, wi, depth), "(a) CMRWIs of P0..P5"},
                    {picture(c.fig6, cmr, depth), "(b) CMRs of P0..P5"}});
  f.rows.push_back({{moved_picture(c.fig6c, *cmr[5], c.fig6.points()[5], 5, depth), "(c) P5 moved within its CMR"},
                    {draw::CurvaturePlot{&c.fig6c, &ac}, "(d) curvature plot of (c): decreasing"}});
  f.caption = "A class A quintic (legs turning by 0.35 rad and growing by 1.15: decreasing curvature) with P5 "
              "pulled in to (3.6,4.3), which breaks monotonicity. Only P4 and P5 keep small regions, as the paper "
              "notes is typical of higher degrees; P5 at (4,5) restores decreasing curvature.";
  b.write("fig6", std::move(f));
}

void figure7(Builder& b, const Curves& c) {
  const View v = square_view(0.9, -0.8, 2.8);
  const int depth = b.options().depth;
  draw::Figure f;
  f.title = "Fig. 7: the subdivision level at which each position was decided (CMRWIs of a cubic)";
  f.rows.emplace_back();
  long undecided = 0, deep_monotone = 0, deep_not = 0, mismatch = 0;
  for (int k = 0; k < 4; ++k) {
    const RegionResult& r = b.region(c.fig2, k, Mode::cmrwi, v);
    const RegionResult& r0 = b.region(c.fig2, k, Mode::cmrwi, v, {}, 0);
    undecided += count(r, 3);
    auto monotone_at = [](const RegionResult& m, std::size_t i) {
      return m.labels[i] == Direction::increasing || m.labels[i] == Direction::decreasing;
    };
    for (std::size_t i = 0; i < r.labels.size(); ++i) {
      const bool monotone = monotone_at(r, i);
      deep_monotone += monotone && r.depth[i] > 0;
      deep_not += r.labels[i] == Direction::none && r.depth[i] > 0;
      // Level 0 of a depth-D run must be what a depth-0 run decides as monotone.
      const bool level0 = monotone && r.depth[i] == 0;
      mismatch += level0 != monotone_at(r0, i) || (level0 && r0.labels[i] != r.labels[i]);
    }
    draw::RegionPicture p = picture(c.fig2, {&r}, depth);
    p.depth_shading = true;
    f.rows.back().push_back({p, "(" + std::string(1, static_cast<char>('a' + k)) + ") P" + std::to_string(k)});
  }
  b.claim("Fig. 7", "no position is left undecided at the depth limit", undecided == 0,
          std::to_string(undecided) + " undecided px");
  b.claim("Fig. 7", "some positions need subdivision both to confirm and to refute monotonicity",
          deep_monotone > 0 && deep_not > 0,
          std::to_string(deep_monotone) + " monotone and " + std::to_string(deep_not) +
              " not monotone px at level > 0");
  b.claim("Fig. 7", "the lightest shade is exactly the level-0 (sufficient condition) region", mismatch == 0,
          std::to_string(mismatch) + " px differ from a depth-0 run");
  f.caption = "Red and blue are darker the deeper Algorithm 1 had to subdivide to confirm monotonicity; grey is "
              "darker the deeper it went to refute it. The lightest red and blue are the positions where all "
              "coefficients of lambda already have one sign, the sufficient condition of the paper's ref. [16]. "
              "Same cubic as Figs. 2 and 3.";
  b.write("fig7", std::move(f));
}

void figure8(Builder& b, const Curves& c) {
  const View v = default_view(c.fig8, b.options().size, b.options().size);
  const auto cmr = all_points(b, c.fig8, Mode::cmr, v);
  bool exact = true;
  std::string detail;
  for (int k = 0; k < 6; ++k) {
    const bool want = k >= 1 && k <= 3;
    exact = exact && count(*cmr[k], 2) == 0 && (want ? count(*cmr[k], 1) > 0 : count(*cmr[k], 1) == 0);
    detail += (k ? "; P" : "P") + std::to_string(k) + " " + counts(*cmr[k]);
  }
  b.claim("Fig. 8a", "CMRs exist for exactly P1, P2, P3 (none for P0, P4, P5 in the view), all red", exact, detail);
  const SplineAnalysis& ab = b.analysis(c.fig8b);
  const Vec2 p3 = c.fig8b.points()[3];
  const uint8_t l = label_at(*cmr[3], p3);
  bool clockwise = true;
  for (const SegmentClass& s : ab.segments) clockwise = clockwise && s.inflection.kappa_sign < 0;
  b.claim("Fig. 8b", "P3 moved into its CMR: curvature negative (clockwise) and increasing over the whole curve",
          l == 1 && ab.cmr == Direction::increasing && clockwise,
          "P3 at " + point_text(p3) + ": " + label_text(l) + ", analyze cmr " + to_string(ab.cmr) +
              (clockwise ? ", kappa < 0" : ", kappa not negative throughout"));
  const int depth = b.options().depth;
  draw::Figure f;
  f.title = "Fig. 8: CMRs of a cubic B-spline with knots [0,1,2,3,4,5,6,7]";
  f.rows.push_back({{picture(c.fig8, cmr, depth), "(a) CMRs of P0..P5"},
                    {draw::CurvaturePlot{&c.fig8, &b.analysis(c.fig8)}, "curvature plot of (a)"}});
  f.rows.push_back({{moved_picture(c.fig8b, *cmr[3], c.fig8.points()[3], 3, depth), "(b) P3 moved within its CMR"},
                    {draw::CurvaturePlot{&c.fig8b, &ab}, "curvature plot of (b): increasing"}});
  f.caption = "Six points placed clockwise, so the curvature is negative and the regions are red (increasing). "
              "The polygon is a clockwise spiral hill-climbed so that the first two segments both fail: P0 acts on "
              "the first segment only and P4, P5 not on it at all, so only P1, P2, P3 can repair the curve. The "
              "regions are thin: the three segments leave one point little freedom.";
  b.write("fig8", std::move(f));
}

void figure9_10(Builder& b, const Curves& c) {
  const View v = square_view(3.6, -3.6, 4.8);
  const auto cmr = all_points(b, c.fig9, Mode::cmr, v);
  const SplineAnalysis& a = b.analysis(c.fig9);
  b.claim("Fig. 9a", "the curve is not monotone and P3 has a red CMR",
          a.cmr == Direction::none && count(*cmr[3], 1) > 0 && count(*cmr[3], 2) == 0,
          std::string("analyze cmr ") + to_string(a.cmr) + "; P3 " + counts(*cmr[3]));
  const SplineAnalysis& ab = b.analysis(c.fig9b);
  const Vec2 p3 = c.fig9b.points()[3];
  const uint8_t l = label_at(*cmr[3], p3);
  b.claim("Fig. 9b", "P3 moved into its CMR: the curvature increases over the whole curve",
          l == 1 && ab.cmr == Direction::increasing,
          "P3 at " + point_text(p3) + ": " + label_text(l) + ", analyze cmr " + to_string(ab.cmr));
  const int depth = b.options().depth;
  draw::Figure f;
  f.title = "Fig. 9: CMRs of a cubic B-spline with knots [0,0,0,1,2,3,3,3]";
  f.rows.push_back({{picture(c.fig9, cmr, depth), "(a) CMRs of P0..P5"},
                    {draw::CurvaturePlot{&c.fig9, &a}, "curvature plot of (a)"}});
  f.rows.push_back({{moved_picture(c.fig9b, *cmr[3], c.fig9.points()[3], 3, depth), "(b) P3 moved within its CMR"},
                    {draw::CurvaturePlot{&c.fig9b, &ab}, "curvature plot of (b): increasing"}});
  f.caption = "A clockwise class A cubic (legs turning by -0.5 rad and growing by 2.5, so |kappa| falls and kappa "
              "rises) written on the clamped knots, with P3 pulled in to (1.5,-1); only P3 can repair it. (b) puts "
              "P3 back where the polynomial had it, (3.46,-2.1).";
  b.write("fig9", std::move(f));

  // Fig. 10: P5's split map at joint 2 (spans 0-1 against span 2, CMR mode).
  const RegionResult& sp = b.region(c.fig9b, 5, Mode::cmr, v, 2);
  b.claim("Fig. 10", "P5's split map at the joint u = 2 has inc-dec and inc-inc positions",
          count(sp, 2) > 0 && count(sp, 1) > 0, split_counts(sp));
  const SplineAnalysis& xa = b.analysis(c.fig10a, 2);
  const Vec2 pa = c.fig10a.points()[5];
  const uint8_t la = label_at(sp, pa);
  b.claim("Fig. 10a", "P5 in the inc-dec region: a curvature maximum at the joint u = 2",
          la == 2 && xa.split == Split::inc_dec,
          "P5 at " + point_text(pa) + ": " + label_text(la) + ", analyze split " +
              (xa.split ? to_string(*xa.split) : "-"));
  // The paper's maximum is of signed kappa; the curve runs clockwise (kappa <
  // 0), so by |kappa| the joint is the flattest point (docs/semantics.md).
  std::optional<ExtremumKind> kind;
  if (xa.split) kind = split_extremum_kind(*xa.split, xa.joints[1]);
  b.claim("Fig. 10a", "read by |kappa|: the clockwise curve's signed maximum at u = 2 is its flattest point",
          kind.has_value() && *kind == ExtremumKind::flattest,
          std::string("kappa at the joint ") + std::to_string(xa.joints[1].kappa_left) + " | " +
              std::to_string(xa.joints[1].kappa_right) + ": " + (kind ? to_string(*kind) : "no extremum"));
  const SplineAnalysis& xb = b.analysis(c.fig10b);
  const Vec2 pb = c.fig10b.points()[5];
  const uint8_t lb = label_at(sp, pb);
  b.claim("Fig. 10b", "P5 in the red (inc-inc) region: the curvature increases over the whole curve",
          lb == 1 && xb.cmr == Direction::increasing,
          "P5 at " + point_text(pb) + ": " + label_text(lb) + ", analyze cmr " + to_string(xb.cmr));
  draw::Figure g;
  g.title = "Fig. 10: creating a curvature extremum at the joint between the 2nd and 3rd segment";
  draw::RegionPicture pa_pic = moved_picture(c.fig10a, sp, c.fig9b.points()[5], 5, depth);
  draw::RegionPicture pb_pic = moved_picture(c.fig10b, sp, c.fig9b.points()[5], 5, depth);
  pa_pic.split = pb_pic.split = true;
  g.rows.push_back({{pa_pic, "(a) P5 in the dark blue (inc-dec) region"},
                    {draw::CurvaturePlot{&c.fig10a, &b.analysis(c.fig10a)}, "curvature plot of (a): maximum at u = 2"}});
  g.rows.push_back({{pb_pic, "(b) P5 in the red (inc-inc) region"},
                    {draw::CurvaturePlot{&c.fig10b, &xb}, "curvature plot of (b): increasing"}});
  g.caption = "Starting from Fig. 9(b), the CMRs of P5 with the curve split at u = 2: segments 0-1 and segment 2 "
              "are judged apart (CMR mode). P5 acts on the last segment only; bent inwards to (5.4,-5.8) it makes "
              "that segment decreasing (a maximum at the joint), placed at (6.5,-6.3) it keeps the whole curve "
              "increasing.";
  b.write("fig10", std::move(g));
}

// ------------------------------------------------------------ Fig. 13 (§5.2) --
//
// A closed κ-curve, its cubic chain (each quadratic split at its curvature
// maximum, Eq. 7, and degree-elevated) and a local modification: P_{k+1}
// moved into its region, P_{k-1} moved onto the new tangent line into its
// region. Each region is that of one cubic piece as a Bézier curve (the other
// handle does not act on it), so both are computed on the unedited chain.

/// Curvature extrema strictly inside a Bézier piece (sign changes of lambda,
/// certified by exact root isolation), farther than `margin` from its ends.
int interior_extrema(const std::vector<Vec2>& piece, double margin) {
  std::vector<Point<Rational>> exact;
  for (const Vec2& p : piece) exact.push_back(to_point<Rational>(p));
  int n = 0;
  for (const RootInterval& r : isolate_roots(lambda_bernstein<Rational>(exact)))
    n += r.sign_change() && double_below(r.lo) > margin && double_above(r.hi) < 1 - margin;
  return n;
}

/// Largest |sin| of the angle between the tangents either side of each joint
/// (and the closing point of a closed chain), and whether every pair points
/// the same way: G1 where the first is ~0 and the second holds.
std::pair<double, bool> g1_defect(const BSpline& chain, bool closed) {
  const auto& P = chain.points();
  const int last = chain.point_count() - 1;
  double worst = 0;
  bool forward = true;
  auto check = [&](Vec2 in, Vec2 out) {
    worst = std::max(worst, std::abs(det(in, out)) / (glm::length(in) * glm::length(out)));
    forward = forward && dot(in, out) > 0;
  };
  for (int j = 3; j < last; j += 3) check(P[j] - P[j - 1], P[j + 1] - P[j]);
  if (closed) check(P[last] - P[last - 1], P[1] - P[0]);
  return {worst, forward};
}

/// Fig. 13a: the iteration converged and each quadratic's curvature maximum
/// (at most one, certified) is at its point, within 1e-7 of the extent.
void claim_kcurve_maxima(Builder& b, const KCurve& kc, const std::vector<Vec2>& points) {
  Vec2 lo = points[0], hi = points[0];
  for (const Vec2& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double extent = glm::length(hi - lo);
  int maxima_at_points = 0;
  for (std::size_t i = 0; i < kc.quadratics.size(); ++i) {
    const auto& q = kc.quadratics[i];
    const double t = kc.t_max[i], u = 1 - t;
    const bool at = glm::length(u * u * q[0] + 2 * t * u * q[1] + t * t * q[2] - points[i]) <= 1e-7 * extent;
    maxima_at_points += at && interior_extrema({q.begin(), q.end()}, 0) <= 1;
  }
  b.claim("Fig. 13a", "the kappa-curve converged and each quadratic's only curvature maximum is at its point",
          kc.converged() && maxima_at_points == static_cast<int>(points.size()),
          std::to_string(maxima_at_points) + " of " + std::to_string(points.size()) + " quadratics, " +
              std::to_string(kc.iterations) + " iterations, residual " + std::to_string(kc.residual));
}

/// Fig. 13's panels: (a) the κ-curve, (b) its cubic chain, (c)/(d) the
/// handles' regions with the moves, (e) the edited chain and its curvature.
void draw_figure13(Builder& b, const std::array<BSpline, 3>& s, const RegionResult& r_before,
                   const RegionResult& r_after, int k) {
  const BSpline &quad = s[0], &chain = s[1], &edited = s[2];
  const int size = b.options().size, depth = b.options().depth;
  const RegionResult* blank = &blank_layer(b, default_view(chain, size, size));  // the whole curve, no region
  draw::Figure f;
  f.title = "Fig. 13: a kappa-curve, its cubic chain and a local modification without a new curvature extremum";
  draw::RegionPicture moved_next = picture(edited, {&r_after}, depth);
  moved_next.moved = std::make_pair(chain.points()[k + 1], edited.points()[k + 1]);
  draw::RegionPicture moved_prev = picture(edited, {&r_before}, depth);
  moved_prev.moved = std::make_pair(chain.points()[k - 1], edited.points()[k - 1]);
  f.rows.push_back({{picture(quad, {blank}, depth), "(a) the kappa-curve (quadratic Bezier chain)"},
                    {picture(chain, {blank}, depth), "(b) split at the maxima, degree-elevated"},
                    {draw::CurvaturePlot{&chain, &b.analysis(chain)}, "curvature plot of (b): maxima at the points"}});
  f.rows.push_back({{moved_next, "(c) P" + std::to_string(k + 1) + " moved within its region"},
                    {moved_prev, "(d) P" + std::to_string(k - 1) + " moved onto the new tangent, in its region"},
                    {draw::CurvaturePlot{&edited, &b.analysis(edited)}, "(e) curvature plot after the move"}});
  f.caption = "The closed kappa-curve through (0,0), (3,-0.5), (5,1), (4,3.2), (1.5,3.5), (-0.5,2) (Yan et al. "
              "2017; curvature maxima only at the points), split at each maximum (Eq. 7) and degree-elevated to "
              "cubics (section 5.2). At the maximum P" + std::to_string(k) + " = (5,1), P" + std::to_string(k + 1) +
              "'s region is that of the cubic after it (blue: decreasing curvature) and P" + std::to_string(k - 1) +
              "'s that of the cubic before it (red: increasing); moving both within them on one line through P" +
              std::to_string(k) + " keeps G1 and the maximum at P" + std::to_string(k) +
              ". Grey bands in (b) are halves whose lambda vanishes at the split point only to rounding: the "
              "maximum is at the joint within about 1e-14 of the parameter, which the exact classifier sees.";
  b.write("fig13", std::move(f));
}

void figure13(Builder& b) {
  // A six-point closed blob, counter-clockwise (κ > 0: the maxima are
  // increasing-then-decreasing). The edited maximum is point 2 = (5, 1), whose
  // two pieces leave the handles regions wide enough to move in.
  const std::vector<Vec2> points{{0, 0}, {3, -0.5}, {5, 1}, {4, 3.2}, {1.5, 3.5}, {-0.5, 2}};
  constexpr int kEdited = 2;
  const KCurve kc = kcurve(points, {.closed = true});
  const BSpline quad = renamed(kcurve_quadratic_spline(kc), "fig13a");
  const BSpline chain = renamed(kcurve_cubic_chain(kc), "fig13b");
  const int k = kcurve_cubic_maxima(kc)[kEdited];
  CMR_CHECK(k >= 3);
  const auto& P = chain.points();
  claim_kcurve_maxima(b, kc, points);

  // The two pieces at P_k, each as a Bezier curve, and their handles' regions.
  const BSpline before = BSpline::bezier({P[k - 3], P[k - 2], P[k - 1], P[k]}, "fig13-before");
  const BSpline after = BSpline::bezier({P[k], P[k + 1], P[k + 2], P[k + 3]}, "fig13-after");
  const double h = 2.5 * std::max(glm::length(P[k + 1] - P[k]), glm::length(P[k - 1] - P[k]));
  const View v = square_view(P[k].x, P[k].y, h);
  const RegionResult& r_after = b.region(after, 1, Mode::cmrwi, v);
  const RegionResult& r_before = b.region(before, 2, Mode::cmrwi, v);
  // The move: P_{k+1} turned by -0.05 rad about P_k and pulled in to 0.9 (rounded
  // to 0.01), P_{k-1} onto the new line at 0.8 of its distance.
  const Vec2 d = P[k + 1] - P[k];
  const double c = std::cos(-0.05), sn = std::sin(-0.05);
  const Vec2 next = glm::round((P[k] + 0.9 * Vec2(c * d.x - sn * d.y, sn * d.x + c * d.y)) * 100.0) / 100.0;
  const Vec2 prev = P[k] - 0.8 * glm::length(P[k - 1] - P[k]) / glm::length(next - P[k]) * (next - P[k]);
  const BSpline edited = renamed(chain.with_point(k + 1, next).with_point(k - 1, prev), "fig13c");
  const uint8_t l_next = label_at(r_after, next), l_prev = label_at(r_before, prev);
  const SplineAnalysis& a_after = b.analysis(after.with_point(1, next));
  const SplineAnalysis& a_before = b.analysis(before.with_point(2, prev));
  b.claim("Fig. 13c", "P_{k+1} moved into its blue region: the piece after P_k keeps decreasing curvature",
          l_next == 2 && a_after.cmrwi == Direction::decreasing,
          "P" + std::to_string(k + 1) + " at " + point_text(next) + ": " + label_text(l_next) + ", analyze " +
              to_string(a_after.cmrwi));
  b.claim("Fig. 13d", "P_{k-1} moved onto the new tangent into its red region: the piece before P_k keeps increasing",
          l_prev == 1 && a_before.cmrwi == Direction::increasing,
          "P" + std::to_string(k - 1) + " at " + point_text(prev) + ": " + label_text(l_prev) + ", analyze " +
              to_string(a_before.cmrwi));
  const BSpline local = BSpline::make(3, {0, 0, 0, 1, 1, 1, 2, 2, 2},
                                      {P[k - 3], P[k - 2], prev, P[k], next, P[k + 2], P[k + 3]}, "fig13-local");
  const SplineAnalysis& a_local = b.analysis(local, 1);
  const int extra = interior_extrema({P[k - 3], P[k - 2], prev, P[k]}, 1e-9) +
                    interior_extrema({P[k], next, P[k + 2], P[k + 3]}, 1e-9);
  b.claim("Fig. 13e", "no new curvature extremum: the maximum stays at P_k, none inside the edited pieces",
          a_local.split == Split::inc_dec && extra == 0,
          std::string("split at P_k: ") + (a_local.split ? to_string(*a_local.split) : "-") + ", " +
              std::to_string(extra) + " interior extrema");
  const auto [g1, forward] = g1_defect(edited, true);
  b.claim("Fig. 13e", "G1 kept at every joint of the edited chain", g1 <= 1e-12 && forward,
          "largest |sin| between tangents " + std::to_string(g1));
  draw_figure13(b, {quad, chain, edited}, r_before, r_after, k);
}

// ------------------------------------------------------ Figs. 11, 12 (§5.1) --
//
// Each piece on its own (RegionRequest::each_piece): a joint point moved with
// its two handles (a rigid group: G1 stays exact) keeps both pieces at it
// monotone, each in either direction.

/// Renders a request on the figures' backend and keeps the image alive.
const RegionResult& render(Builder& b, const BSpline& s, const RegionRequest& request, const std::string& what) {
  const auto t0 = std::chrono::steady_clock::now();
  auto image = std::make_shared<RegionResult>(b.options().backend->render(RegionProblem::make(s, request)));
  std::ostringstream line;
  line << "  " << s.name() << ": " << what << " (" << request.width << 'x' << request.height << ", " << std::fixed
       << std::setprecision(3) << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()
       << " s)";
  b.log(line.str());
  b.keep(image);
  return *image;
}

/// The region request of point k moving with `with`, judged on `range` or
/// each piece on its own.
RegionRequest piece_request(Builder& b, int k, std::vector<int> with, const View& v, std::optional<SegmentRange> range,
                            bool each_piece) {
  RegionRequest o;
  o.point = k;
  o.with = std::move(with);
  o.segments = range;
  o.each_piece = each_piece;
  o.max_depth = b.options().depth;
  o.width = o.height = b.options().size;
  o.view = v;
  o.depth = false;
  return o;
}

/// The centre of the pixel labelled `label` nearest to p (nullopt if none).
std::optional<Vec2> nearest_pixel(const RegionResult& r, uint8_t label, Vec2 p) {
  std::optional<Vec2> best;
  double d = 0;
  for (int j = 0; j < r.height; ++j)
    for (int i = 0; i < r.width; ++i)
      if (r.code_at(static_cast<std::size_t>(j) * r.width + i) == label) {
        const Vec2 c = pixel_center(r.view, r.width, r.height, i, j);
        const double e = glm::length(c - p);
        if (!best || e < d) best = c, d = e;
      }
  return best;
}

/// The spline with point k and its group moved by p - P_k (as the region engine moves them).
BSpline moved_group(const BSpline& s, int k, const std::vector<int>& with, Vec2 p, const std::string& name) {
  const Vec2 d = p - s.points()[k];
  BSpline out = s.with_point(k, p);
  for (int g : with) out = out.with_point(g, s.points()[g] + d);
  return renamed(out, name);
}

bool all_g1(const SplineAnalysis& a) {
  return std::all_of(a.joints.begin(), a.joints.end(), [](const Joint& j) { return j.g1; }) &&
         (!a.seam || a.seam->g1);
}

SplineAnalysis each_piece_analysis(const BSpline& s, int depth) {
  AnalyzeOptions o;
  o.classify.max_depth = depth;
  o.each_piece = true;
  return analyze(s, o);
}

std::string groups_text(const SplineAnalysis& a) {
  std::string t;
  for (Direction d : a.groups) t += (t.empty() ? "" : ", ") + std::string(to_string(d));
  return t;
}

void figure11(Builder& b, const Curves& c) {
  const BSpline& s = c.fig11;
  const int depth = b.options().depth;
  const View v = square_view(2.1, 2.0, 2.6);
  const SplineAnalysis before = each_piece_analysis(s, depth);
  b.claim("Fig. 11", "the two G1 pieces are not each monotone before the move",
          before.each_piece == EachPiece::fail && all_g1(before), "pieces: " + groups_text(before));
  // Q3 (point 2) for the first piece, Q5 (point 4) for the second: each alone.
  const RegionResult& q3 = render(b, s, piece_request(b, 2, {}, v, SegmentRange{0, 0}, false), "Q3, piece 0");
  const RegionResult& q5 = render(b, s, piece_request(b, 4, {}, v, SegmentRange{1, 1}, false), "Q5, piece 1");
  b.claim("Fig. 11", "Q3 has a region for the first piece and Q5 one for the second",
          count(q3, 1) + count(q3, 2) > 0 && count(q5, 1) + count(q5, 2) > 0,
          "Q3 " + counts(q3) + "; Q5 " + counts(q5));
  // Q4 (point 3) with Q3 and Q5 moving with it: each piece on its own.
  const RegionResult& q4 = render(b, s, piece_request(b, 3, {2, 4}, v, {}, true), "Q4 with Q3, Q5, each piece");
  const RegionResult& q4a = render(b, s, piece_request(b, 3, {2, 4}, v, SegmentRange{0, 0}, false), "Q4 group, piece 0");
  const RegionResult& q4b = render(b, s, piece_request(b, 3, {2, 4}, v, SegmentRange{1, 1}, false), "Q4 group, piece 1");
  long mismatch = 0;
  const auto monotone = [](uint8_t l) { return l == 1 || l == 2; };
  for (std::size_t i = 0; i < q4.size(); ++i)
    mismatch += (q4.code_at(i) == code(EachPiece::monotone)) != (monotone(q4a.code_at(i)) && monotone(q4b.code_at(i)));
  b.claim("Fig. 11", "Q4's region (Q3, Q5 moving with it) is exactly where both pieces are monotone",
          count(q4, 1) > 0 && mismatch == 0,
          std::to_string(count(q4, 1)) + " px each-monotone, " + std::to_string(mismatch) +
              " px differ from the intersection of the two pieces' regions");
  const std::optional<Vec2> place = nearest_pixel(q4, code(EachPiece::monotone), s.points()[3]);
  const BSpline after = place ? moved_group(s, 3, {2, 4}, *place, "fig11b") : s;
  const SplineAnalysis a = each_piece_analysis(after, depth);
  b.claim("Fig. 11", "Q4 moved into its region with Q3, Q5: both pieces monotone, G1 kept",
          place && label_at(q4, *place) == 1 && a.each_piece == EachPiece::monotone && all_g1(a),
          (place ? "Q4 at " + point_text(*place) : std::string("no region")) + ": pieces " + groups_text(a) +
              (all_g1(a) ? ", G1" : ", not G1"));
  draw::Figure f;
  f.title = "Fig. 11: two G1 Bezier pieces; the region of the shared point Q4 keeping both monotone";
  draw::RegionPicture handles = picture(s, {&q3, &q5}, depth);
  draw::RegionPicture joint = picture(s, {&q4}, depth);
  joint.each_piece = true;
  joint.points = {3};
  draw::RegionPicture moved_pic = picture(after, {&q4}, depth);
  moved_pic.each_piece = true;
  moved_pic.moved = std::make_pair(s.points()[3], after.points()[3]);
  f.rows.push_back({{handles, "(a) Q3's region for piece 1, Q5's for piece 2"},
                    {joint, "(b) Q4 with Q3, Q5: each piece monotone"}});
  f.rows.push_back({{moved_pic, "(c) Q4 moved into its region"},
                    {draw::CurvaturePlot{&after, &b.analysis(after)}, "curvature plot of (c): each piece monotone"}});
  f.caption = "Q1..Q7 are P0..P6. (a) Q3 acts on the first piece only and Q5 on the second; each region is that "
              "piece judged alone. (b) Q4 moves with Q3 and Q5 (a rigid group, so G1 at Q4 stays exact); green is "
              "where both pieces are monotone, each in either direction on its own (the paper's purple). (c) Q4 "
              "placed at the region's pixel nearest to it.";
  b.write("fig11", std::move(f));
}

/// Fig. 12's start: an apple outline of 8 cubic pieces, G1 at every on-curve
/// point (handles on the tangent of the neighbours' chord, Catmull-Rom), the
/// handle lengths a third of the chord scaled by a seeded factor in
/// 0.5..1.6 so that some pieces have an interior curvature extremum (not
/// rounded: rounding each handle would break the collinearity). An open
/// chain that ends where it starts (J0 and its handles never move, so the
/// closing point stays G1).
BSpline apple_chain() {
  const std::vector<Vec2> J{{0, 3.2}, {-1.6, 3.9}, {-3.2, 2.6}, {-3.0, 0.2}, {-1.3, -1.9},
                            {1.3, -1.9},  {3.0, 0.2},   {3.2, 2.6}};
  const int n = static_cast<int>(J.size());
  std::vector<double> f{1.45, 0.62, 1.3, 0.55, 1.5, 0.7, 1.35, 0.58, 1.2, 0.66, 1.55, 0.6, 1.4, 0.75, 1.25, 0.5};
  std::vector<Vec2> P;
  std::vector<double> knots;
  for (int i = 0; i <= n; ++i) {
    const Vec2 q = J[i % n];
    if (i > 0) {
      const Vec2 t = glm::normalize(J[(i + 1) % n] - J[(i - 1 + n) % n]);
      P.push_back(q - f[2 * (i - 1) + 1] * glm::length(J[i % n] - J[i - 1]) / 3.0 * t);
    }
    P.push_back(q);
    if (i < n) {
      const Vec2 t = glm::normalize(J[(i + 1) % n] - J[(i - 1 + n) % n]);
      P.push_back(q + f[2 * i] * glm::length(J[(i + 1) % n] - q) / 3.0 * t);
    }
  }
  for (int i = 0; i <= n; ++i)
    for (int r = 0; r < 3; ++r) knots.push_back(i);
  return BSpline::make(3, knots, P, "fig12a");
}

/// Fig. 12: the apple's pieces made monotone one joint at a time. A failing
/// piece's inner joint (with its two handles, a rigid group) is moved to the
/// nearest pixel of its each-piece region judged on the two pieces at it
/// (segments j-1..j): the pieces elsewhere are not touched, so each step
/// keeps what the earlier ones repaired.
void figure12(Builder& b) {
  const int depth = b.options().depth;
  BSpline s = apple_chain();
  const BSpline start = s;
  const SplineAnalysis a0 = each_piece_analysis(s, depth);
  const int N = s.segment_count();
  const auto failing = [](const SplineAnalysis& a) {
    int n = 0;
    for (Direction d : a.groups) n += d != Direction::increasing && d != Direction::decreasing;
    return n;
  };
  b.claim("Fig. 12a", "the apple: 8 G1 cubic pieces, some of them not monotone",
          N == 8 && failing(a0) > 0 && all_g1(a0), std::to_string(failing(a0)) + " of " + std::to_string(N) +
                                                          " pieces not monotone: " + groups_text(a0));
  std::vector<std::string> steps;
  bool steps_ok = true;
  std::vector<const RegionResult*> shown;
  std::vector<BSpline> states;
  for (int round = 0; round < 3 && failing(each_piece_analysis(s, depth)) > 0; ++round) {
    for (int piece = 0; piece < N; ++piece) {
      const SplineAnalysis a = each_piece_analysis(s, depth);
      if (a.groups[piece] == Direction::increasing || a.groups[piece] == Direction::decreasing) continue;
      for (int j : {piece + 1, piece}) {  // the joint after the piece, then the one before
        if (j < 1 || j > N - 1) continue;
        const int k = 3 * j;
        const Vec2 q = s.points()[k];
        const double half = 0.6 * std::max(glm::length(s.points()[k + 3] - q), glm::length(s.points()[k - 3] - q));
        const RegionResult& r = render(b, s, piece_request(b, k, {k - 1, k + 1}, square_view(q.x, q.y, half),
                                                           SegmentRange{j - 1, j}, true),
                                       "J" + std::to_string(j) + " with its handles, pieces " +
                                           std::to_string(j - 1) + ".." + std::to_string(j));
        const std::optional<Vec2> place = nearest_pixel(r, code(EachPiece::monotone), q);
        if (!place) continue;
        const BSpline next = moved_group(s, k, {k - 1, k + 1}, *place, "fig12");
        const SplineAnalysis an = each_piece_analysis(next, depth);
        const bool ok = an.groups[j - 1] != Direction::none && an.groups[j] != Direction::none &&
                        an.groups[j - 1] != Direction::undecided && an.groups[j] != Direction::undecided;
        steps_ok = steps_ok && ok && label_at(r, *place) == 1;
        steps.push_back("J" + std::to_string(j) + " to " + point_text(*place));
        s = next;
        shown.push_back(&r);
        states.push_back(s);
        break;
      }
    }
  }
  const BSpline final_chain = renamed(s, "fig12g");
  const SplineAnalysis af = each_piece_analysis(final_chain, depth);
  const bool closed = glm::length(final_chain.points().back() - final_chain.points().front()) == 0;
  b.claim("Fig. 12b-f", "each move puts a joint (with its handles) into its region: both pieces at it monotone",
          steps_ok && !steps.empty(), std::to_string(steps.size()) + " moves: " + [&] {
            std::string t;
            for (const std::string& x : steps) t += (t.empty() ? "" : "; ") + x;
            return t;
          }());
  b.claim("Fig. 12g", "the final apple: every piece monotone on its own, G1 at every joint, closed",
          af.each_piece == EachPiece::monotone && all_g1(af) && closed && g1_defect(final_chain, true).first <= 1e-12,
          "pieces: " + groups_text(af));
  draw::Figure f;
  f.title = "Fig. 12: an apple of 8 G1 Bezier pieces made monotone piece by piece through the regions";
  const RegionResult* blank = &blank_layer(b, default_view(start, b.options().size, b.options().size));
  std::vector<draw::Panel> row1{{picture(start, {blank}, depth), "(a) the apple as drawn"},
                                {draw::CurvaturePlot{&start, &b.analysis(start)}, "curvature plot of (a)"}};
  f.rows.push_back(row1);
  for (std::size_t i = 0; i < shown.size() && i < 4; i += 2) {
    std::vector<draw::Panel> row;
    for (std::size_t m = i; m < shown.size() && m < i + 2; ++m) {
      draw::RegionPicture p = picture(states[m], {shown[m]}, depth);
      p.each_piece = true;
      row.push_back({p, "(" + std::string(1, static_cast<char>('b' + m)) + ") " + steps[m]});
    }
    f.rows.push_back(row);
  }
  // The next letter after the steps shown (b.. for up to four of them).
  const std::string last = "(" + std::string(1, static_cast<char>('b' + std::min<std::size_t>(shown.size(), 4))) + ")";
  f.rows.push_back({{picture(final_chain, {blank}, depth), last + " the final apple"},
                    {draw::CurvaturePlot{&final_chain, &b.analysis(final_chain)}, "curvature plot of " + last}});
  f.caption = "The apple's outline (core and leaf left out): 8 cubic pieces with G1 at the on-curve points "
              "(handles on the Catmull-Rom tangents, their lengths scaled by fixed factors so that some pieces "
              "have a curvature extremum inside). Each step moves one on-curve point with its two handles (G1 "
              "stays exact) to the nearest position of its region where both pieces at it are monotone, each "
              "in either direction; the other pieces are untouched. Green: that region.";
  b.write("fig12", std::move(f));
}

/// The figure a claim belongs to: "Fig. 10a" -> "fig10".
std::string figure_id(const Claim& c) {
  std::string id = "fig";
  for (std::size_t i = c.figure.find_first_of("0123456789");
       i < c.figure.size() && std::isdigit(static_cast<unsigned char>(c.figure[i])); ++i)
    id += c.figure[i];
  return id;
}

void write_index(Builder& b) {
  const FiguresResult& r = b.result();
  std::ostringstream h;
  h << "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>cmr: the paper's figures</title>\n"
       "<style>body{font-family:sans-serif;max-width:1700px;margin:2em auto;padding:0 1em;color:#222}"
       "img{max-width:100%;border:1px solid #ccc}table{border-collapse:collapse;margin:.5em 0 2em}"
       "td,th{border:1px solid #ccc;padding:3px 8px;text-align:left;vertical-align:top}"
       ".PASS{color:#080;font-weight:bold}.FAIL{color:#c00;font-weight:bold}</style></head><body>\n"
       "<h1>Yoshida et al., CAD&amp;A 21(1) 2024, Section 4: figures recomputed by cmr</h1>\n<p>"
    << r.claims.size() << " claims, "
    << std::count_if(r.claims.begin(), r.claims.end(), [](const Claim& c) { return !c.pass; })
    << " failed. Regions " << b.options().size << "x" << b.options().size << " px, depth "
    << b.options().depth << ". The curves are the spline files next to this page.</p>\n";
  for (const FigureFile& f : r.figures) {
    h << "<h2>" << html_escape(f.title) << "</h2>\n<img src=\"" << f.id << ".png\" alt=\"" << html_escape(f.title)
      << "\">\n<p>" << html_escape(f.caption)
      << "</p>\n<table><tr><th>claim</th><th>result</th><th>measured</th></tr>\n";
    for (const Claim& c : r.claims) {
      if (figure_id(c) != f.id) continue;
      h << "<tr><td>" << html_escape(c.figure + ": " + c.text) << "</td><td class=\"" << (c.pass ? "PASS" : "FAIL")
        << "\">" << (c.pass ? "PASS" : "FAIL") << "</td><td>" << html_escape(c.detail) << "</td></tr>\n";
    }
    h << "</table>\n";
  }
  h << "<h2>Spline files</h2>\n<p>";
  for (const BSpline& s : figure_splines())
    h << "<a href=\"" << s.name() << ".json\">" << s.name() << ".json</a> ";
  h << "</p>\n</body></html>\n";
  const std::filesystem::path path = b.options().out / "index.html";
  b.out().stage(path, h.str());
  b.result().written.push_back(path);
}

}  // namespace

bool FiguresResult::all_pass() const {
  return std::all_of(claims.begin(), claims.end(), [](const Claim& c) { return c.pass; });
}

std::vector<BSpline> figure_splines() {
  const Curves c;
  return {c.fig1a,  c.fig2,   c.fig2x[0], c.fig2x[1], c.fig2x[2], c.fig2x[3], c.fig4,   c.fig4x[0], c.fig4x[1],
          c.fig4x[2], c.fig4x[3], c.fig5,   c.fig5c,  c.fig5d,    c.fig6,     c.fig6c,    c.fig8,   c.fig8b,
          c.fig9,     c.fig9b,    c.fig10a, c.fig10b, c.fig11};
}

FiguresResult make_figures(const FiguresOptions& options) {
  if (options.size < 64 || options.size > 4096)
    throw InputError("size " + std::to_string(options.size) + " is outside 64..4096");
  if (options.depth < 0 || options.depth > kMaxDepth)
    throw InputError("depth " + std::to_string(options.depth) + " is outside 0.." + std::to_string(kMaxDepth));
  // Every file is staged and committed at the end as one set: a run that
  // fails (no Vulkan device, a full disk) leaves the folder as it was, and
  // removes it again if it created it.
  OutputSet out;
  out.create_folder(options.out);
  Builder b(options, out);
  const Curves c;
  for (const BSpline& s : figure_splines()) {
    const std::filesystem::path path = options.out / (s.name() + ".json");
    out.stage(path, spline_to_json(s).dump(2) + "\n");
    b.result().written.push_back(path);
  }
  b.log("fig1: lambda of a monotone and a non-monotone cubic (section 3)");
  figure1(b, c);
  b.log("fig2..fig7: Bezier curves (section 4.1)");
  figure2(b, c);
  figure3(b, c);
  figure4(b, c);
  figure5(b, c);
  figure6(b, c);
  figure7(b, c);
  b.log("fig8..fig10: B-spline curves (section 4.2)");
  figure8(b, c);
  figure9_10(b, c);
  b.log("fig11: the region of a shared joint point keeping both pieces monotone (section 5.1)");
  figure11(b, c);
  b.log("fig12: an apple of 8 G1 pieces made monotone through the regions (section 5.1)");
  figure12(b);
  b.log("fig13: a kappa-curve and a local modification (section 5.2)");
  figure13(b);
  write_index(b);
  out.commit();
  b.log("wrote " + std::to_string(b.result().written.size()) + " files into " + options.out.string());
  return std::move(b.result());
}

}  // namespace cmr::fig
