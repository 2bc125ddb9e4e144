// The nearest certified repair (design/fix.hpp) against the two ways it
// replaces, on seeded failing curves (docs/fix.md):
//   cubic   random cubic Beziers with monotone curvature, one inner point
//           nudged (at most 3% of the size) until it is not (seeded);
//   fig8    the Fig. 8 B-spline with its points jittered (seeded);
//   glyphs  DejaVu Sans A-Z a-z 0-9 contours that fail curvature-extrema-at-nodes
//           (TrueType: quadratic B-spline contours);
//   nimbus  the same for Nimbus Sans (CFF: cubic Bezier contours).
// Each case is judged by the requirement curvature-extrema-at-nodes (every segment's
// curvature monotone: a curvature extremum only at a node); three methods:
//   certified  fix(): the best single unit (keep g1), several when needed;
//   tangent    the tangent line search `cmr report` offered before the
//              certified fix (bench_fix_tangent.hpp: one handle along a
//              tangent in steps of 1..64 grid units; grid = 1 font unit, or
//              size/256); the smallest suggestion that makes the gate pass;
//   fairing    minimise a discretised integral of (dkappa/ds)^2 by moving the
//              points the certified fix moved (a compass search, no
//              certification), then judged by analyze.
// Per set and method: share fixed, share of single-violation cases fixed by
// one point, median and worst displacement relative to the curve size, median,
// 90th percentile and worst time per case, and how many cases took over 1 s.
//   build/tools/bench/bench_fix [FONT] [CASES] [SET] [CFF_FONT] [METHODS]
// SET: cubic, fig8, glyphs or nimbus (default, or "all": all four);
// METHODS: comma-separated certified, tangent, fairing (default: all three;
// fairing moves the points the certified fix moved, so it needs certified).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <thread>

#include "design/fix.hpp"
#include "io/font.hpp"
#include "report/batch.hpp"
#include "report/report.hpp"
#include "spline/curvature.hpp"
#include "tools/bench/bench_fix_tangent.hpp"

namespace {

using namespace cmr;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string processor() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown processor";
}

double size_of(const BSpline& s) {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (int k = 0; k < s.unique_point_count(); ++k) {
    x0 = std::min(x0, s.points()[k].x), x1 = std::max(x1, s.points()[k].x);
    y0 = std::min(y0, s.points()[k].y), y1 = std::max(y1, s.points()[k].y);
  }
  return std::hypot(x1 - x0, y1 - y0);
}

const FixRequirement kReq = [] {
  FixRequirement r;
  r.kind = FixRequirement::Kind::extrema_at_nodes;
  return r;
}();

bool passes(const BSpline& s) { return requirement_holds(s, kReq); }

int violations(const BSpline& s) {
  const SplineAnalysis a = analyze(s, fix_analyze_options(kReq));
  return static_cast<int>(failing_segments(s, a, kReq).size());
}

struct Outcome {
  bool fixed = false;
  int points = 0;        // points moved
  double relative = 0;   // largest displacement / size
  double seconds = 0;
};

Outcome certified(const BSpline& s, std::vector<int>* moved) {
  Outcome o;
  const auto t = Clock::now();
  FixRequest r;
  r.requirement = kReq;
  r.threads = 2;
  const FixResult f = fix(s, r);
  o.seconds = since(t);
  o.fixed = f.fixed;
  o.points = static_cast<int>(f.moves.size());
  o.relative = f.max_distance / f.size;
  for (const PointMove& m : f.moves) moved->push_back(m.point);
  if (moved->empty())
    for (const UnitFix& u : f.units) moved->insert(moved->end(), u.points.begin(), u.points.end());
  return o;
}

Outcome tangent(const BSpline& s, double grid) {
  Outcome o;
  const auto t = Clock::now();
  report::ReportOptions opt;
  report::parse_require_list("curvature-extrema-at-nodes", opt);
  opt.regions = false;
  opt.certified_fixes = false;
  opt.threads = 1;
  const report::SplineReport rep = report::judged_report(s, opt);
  for (const bench::TangentMove& f : bench::tangent_line_search(rep, opt, grid)) {
    const BSpline m = s.with_point(f.point, f.to);
    if (passes(m)) {
      o.fixed = true;
      o.points = 1;
      o.relative = std::hypot(f.to.x - f.from.x, f.to.y - f.from.y) / size_of(s);
      break;
    }
  }
  o.seconds = since(t);
  return o;
}

/// A discretised integral of (dkappa/ds)^2 ds over every segment.
double energy(const BSpline& s) {
  double e = 0;
  for (const Segment& seg : s.segments()) {
    const int n = 32;
    double prev_k = 0;
    Vec2 prev_p(0.0);
    for (int i = 0; i <= n; ++i) {
      const double t = seg.a + (seg.b - seg.a) * i / n;
      const CurvatureSample c = curvature_at(s, t);
      if (!std::isfinite(c.kappa)) return 1e300;
      if (i > 0) {
        const double ds = std::hypot(c.point.x - prev_p.x, c.point.y - prev_p.y);
        if (ds > 0) e += (c.kappa - prev_k) * (c.kappa - prev_k) / ds;
      }
      prev_k = c.kappa, prev_p = c.point;
    }
  }
  return e;
}

Outcome fairing(const BSpline& s, const std::vector<int>& points) {
  Outcome o;
  const auto t = Clock::now();
  if (points.empty()) return o;
  const double size = size_of(s);
  BSpline cur = s;
  double e = energy(cur), h = size / 16;
  for (int it = 0; it < 400 && h > 1e-6 * size; ++it) {
    bool improved = false;
    for (int k : points)
      for (const Vec2 d : {Vec2(h, 0), Vec2(-h, 0), Vec2(0, h), Vec2(0, -h)}) {
        const BSpline trial = cur.with_point(k, cur.points()[k] + d);
        const double et = energy(trial);
        if (et < e) cur = trial, e = et, improved = true;
      }
    if (!improved) h /= 2;
  }
  o.seconds = since(t);
  o.fixed = passes(cur);
  double worst = 0;
  for (int k : points) {
    const Vec2 d = cur.points()[k] - s.points()[k];
    if (d != Vec2(0.0)) ++o.points;
    worst = std::max(worst, std::hypot(d.x, d.y));
  }
  o.relative = worst / size;
  return o;
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Row {
  std::vector<Outcome> all;
  std::vector<bool> single;  // the case has one violating segment
};

void print(const char* set, const char* method, const Row& r) {
  int fixed = 0, singles = 0, single_one = 0;
  std::vector<double> rel, secs;
  for (std::size_t i = 0; i < r.all.size(); ++i) {
    const Outcome& o = r.all[i];
    secs.push_back(o.seconds);
    if (r.single[i]) ++singles, single_one += o.fixed && o.points == 1;
    if (!o.fixed) continue;
    ++fixed;
    rel.push_back(o.relative);
  }
  const double worst_rel = rel.empty() ? NAN : *std::max_element(rel.begin(), rel.end());
  std::vector<double> sorted = secs;
  std::sort(sorted.begin(), sorted.end());
  const double p90 = sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(std::ceil(0.9 * sorted.size())) - 1)];
  const long over = std::count_if(secs.begin(), secs.end(), [](double t) { return t > 1.0; });
  std::fflush(stdout);
  std::printf("| %s | %s | %zu | %.1f%% | %d/%d | %.4f | %.4f | %.1f | %.1f | %.1f | %ld |\n", set, method, r.all.size(),
              100.0 * fixed / std::max<std::size_t>(1, r.all.size()), single_one, singles, median(rel), worst_rel,
              1e3 * median(secs), 1e3 * p90, 1e3 * sorted.back(), over);
  std::fflush(stdout);
}

std::string methods = "certified,tangent,fairing";
bool method_on(const char* m) { return methods.find(m) != std::string::npos; }

void run_set(const char* set, const std::vector<BSpline>& cases, double grid_units) {
  Row cert, tang, fair;
  for (const BSpline& s : cases) {
    const bool single = violations(s) == 1;
    std::vector<int> moved;
    cert.all.push_back(method_on("certified") ? certified(s, &moved) : Outcome{});
    tang.all.push_back(method_on("tangent") ? tangent(s, grid_units > 0 ? grid_units : size_of(s) / 256) : Outcome{});
    fair.all.push_back(method_on("fairing") ? fairing(s, moved) : Outcome{});
    cert.single.push_back(single), tang.single.push_back(single), fair.single.push_back(single);
    std::fprintf(stderr, "%s %zu: certified %s %.0f ms, tangent %s %.0f ms, fairing %s %.0f ms\n", set, cert.all.size(),
                 cert.all.back().fixed ? "fixed" : "-", 1e3 * cert.all.back().seconds, tang.all.back().fixed ? "fixed" : "-",
                 1e3 * tang.all.back().seconds, fair.all.back().fixed ? "fixed" : "-", 1e3 * fair.all.back().seconds);
  }
  if (method_on("certified")) print(set, "certified", cert);
  if (method_on("tangent")) print(set, "tangent", tang);
  if (method_on("fairing")) print(set, "fairing", fair);
}

}  // namespace

int main(int argc, char** argv) {
  const char* font = argc > 1 ? argv[1] : "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  const int n = argc > 2 ? std::atoi(argv[2]) : 40;
  std::string only = argc > 3 ? argv[3] : "";  // one set: cubic, fig8, glyphs or nimbus
  if (only == "all") only.clear();
  const char* cff = argc > 4 ? argv[4] : "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf";
  if (argc > 5) methods = argv[5];
  std::printf("bench_fix: %s, %u hardware threads, fix on 2 threads\n\n", processor().c_str(),
              std::thread::hardware_concurrency());
  std::printf("| set | method | cases | fixed | single fixed by one point | median move | worst move | median ms | p90 ms | worst ms | over 1 s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::vector<BSpline> cubics;
  // Near the boundary: a random cubic that passes, one inner point nudged
  // by at most 3% of its size until it fails.
  while (static_cast<int>(cubics.size()) < n) {
    const BSpline s = BSpline::bezier({{0, 0}, {1 + 0.5 * U(rng), 0.8 * U(rng)}, {2 + 0.5 * U(rng), 0.8 * U(rng)}, {3, 0.6 * U(rng)}});
    if (!passes(s)) continue;
    for (int tries = 0; tries < 20; ++tries) {
      const int k = 1 + static_cast<int>(rng() % 2);
      const BSpline m = s.with_point(k, s.points()[k] + 0.03 * size_of(s) * Vec2(U(rng), U(rng)));
      if (!passes(m)) {
        cubics.push_back(m);
        break;
      }
    }
  }
  if (only.empty() || only == "cubic") run_set("cubic", cubics, 0);
  std::vector<BSpline> fig8;
  const std::vector<Vec2> f8 = {{1.3, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95}, {-6.78, -9.78}};
  while (static_cast<int>(fig8.size()) < n) {
    std::vector<Vec2> p = f8;
    for (std::size_t k = 1; k + 1 < p.size(); ++k) p[k] += 0.4 * Vec2(U(rng), U(rng));
    const BSpline s = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, p);
    if (!passes(s)) fig8.push_back(s);
  }
  if (only.empty() || only == "fig8") run_set("fig8", fig8, 0);
  // The first n failing contours of a font's A-Z a-z 0-9.
  auto failing_contours = [&](const char* path) {
    std::vector<BSpline> out;
    const import::Font f = import::read_font(path, import::parse_glyph_spec("A-Z,a-z,0-9"));
    for (const import::Glyph& g : f.glyphs)
      for (const import::Contour& c : g.contours)
        if (static_cast<int>(out.size()) < n && !passes(c.spline)) out.push_back(c.spline);
    return out;
  };
  if (only.empty() || only == "glyphs") run_set("glyphs", failing_contours(font), 1);
  if (only.empty() || only == "nimbus") run_set("nimbus", failing_contours(cff), 1);
  return 0;
}
