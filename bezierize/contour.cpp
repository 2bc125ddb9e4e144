// Marching squares on a region's label map with certified refinement
// (algorithm and contracts: contour.hpp).
#include "bezierize/contour.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include "spline/errors.hpp"
#include "spline/parallel.hpp"

namespace cmr {
namespace {

constexpr std::uint8_t kPad = 255;  // the padding ring: never a label

std::uint8_t code_of(const RegionPixel& p, bool split) { return split ? code(p.split_label) : code(p.label); }

/// The padded sample grid: sample (si, sj), sj = 0 the top padding row; pixel
/// (i, j) is sample (i + 1, j + 1).
struct Grid {
  int W = 0, H = 0, SW = 0, SH = 0;
  View view;
  std::vector<std::uint8_t> codes;  // of the pixels, row-major

  std::uint8_t label(int si, int sj) const {
    if (si <= 0 || sj <= 0 || si > W || sj > H) return kPad;
    return codes[static_cast<std::size_t>(sj - 1) * W + (si - 1)];
  }
  Vec2 centre(int si, int sj) const { return pixel_center(view, W, H, si - 1, sj - 1); }
  std::int64_t sample(int si, int sj) const { return static_cast<std::int64_t>(sj) * SW + si; }
};

/// An edge of the sample grid: from sample (si, sj) to its right (horizontal)
/// or lower (vertical) neighbour.
struct Edge {
  int si = 0, sj = 0;
  bool vertical = false;
  std::int64_t id(const Grid& g) const { return 2 * g.sample(si, sj) + (vertical ? 1 : 0); }
  int bi() const { return vertical ? si : si + 1; }
  int bj() const { return vertical ? sj + 1 : sj; }
};

struct Bracket {
  double lo = 0, hi = 1;
  std::uint8_t hi_label = 0;
};

Vec2 along(Vec2 a, Vec2 b, double t) { return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t}; }

/// Bisection from a (label L) towards b (label b_label != L); see contour.hpp.
Bracket bisect(const RegionProblem& problem, bool split, Vec2 a, Vec2 b, std::uint8_t L, std::uint8_t b_label,
               double stop) {
  Bracket r{0, 1, b_label};
  for (;;) {
    const Vec2 plo = along(a, b, r.lo), phi = along(a, b, r.hi);
    if (std::hypot(phi.x - plo.x, phi.y - plo.y) <= stop) break;
    const double mid = 0.5 * (r.lo + r.hi);
    if (!(r.lo < mid && mid < r.hi)) break;
    const std::uint8_t m = code_of(problem.classify(along(a, b, mid)), split);
    if (m == L) {
      r.lo = mid;
    } else {
      r.hi = mid;
      r.hi_label = m;
    }
  }
  return r;
}

/// One refined vertex: the bracket's midpoint, from the end `from_a`.
struct Refined {
  Edge edge;
  bool from_a = true;
  std::uint8_t label = 0;  // the label kept at the bracket's start
  Bracket bracket;
};

class LabelBuilder {
 public:
  LabelBuilder(const Grid& g, std::uint8_t L, const std::unordered_map<std::int64_t, Vec2>& refined_at)
      : g_(g), L_(L), refined_at_(refined_at) {
    out_.label = L;
  }

  LabelContours build() {
    for (int cj = 0; cj + 1 < g_.SH; ++cj)
      for (int ci = 0; ci + 1 < g_.SW; ++ci) cell(ci, cj);
    chain();
    return std::move(out_);
  }

 private:
  bool in(int si, int sj) const { return g_.label(si, sj) == L_; }

  int corner_vertex(int si, int sj) {
    auto [it, fresh] = corners_.try_emplace(g_.sample(si, sj), 0);
    if (fresh) it->second = add(g_.centre(si, sj), false);
    return it->second;
  }

  int add(Vec2 p, bool refined) {
    out_.vertices.push_back(p);
    out_.refined.push_back(refined);
    return static_cast<int>(out_.vertices.size()) - 1;
  }

  /// The vertex on the edge between samples p and q (one in L, one not).
  int edge_vertex(int pi, int pj, int qi, int qj) {
    Edge e;
    if (pj == qj) e = {std::min(pi, qi), pj, false};
    else e = {pi, std::min(pj, qj), true};
    auto [it, fresh] = edges_.try_emplace(e.id(g_), 0);
    if (!fresh) return it->second;
    const bool p_pad = g_.label(pi, pj) == kPad, q_pad = g_.label(qi, qj) == kPad;
    if (p_pad || q_pad) {
      // Clip to the view's edge: the real sample's centre moved onto it.
      const int ri = p_pad ? qi : pi, rj = p_pad ? qj : pj, ai = p_pad ? pi : qi, aj = p_pad ? pj : qj;
      Vec2 c = g_.centre(ri, rj);
      if (ai == 0) c.x = g_.view.x0;
      if (ai == g_.W + 1) c.x = g_.view.x1;
      if (aj == 0) c.y = g_.view.y1;
      if (aj == g_.H + 1) c.y = g_.view.y0;
      it->second = add(c, false);
    } else {
      it->second = add(refined_at_.at(2 * e.id(g_) + (L_ == g_.label(e.si, e.sj) ? 0 : 1)), true);
    }
    return it->second;
  }

  void cell(int ci, int cj) {
    const std::array<std::array<int, 2>, 4> c = {{{ci, cj + 1}, {ci + 1, cj + 1}, {ci + 1, cj}, {ci, cj}}};
    std::array<bool, 4> inside{};
    int count = 0;
    for (int k = 0; k < 4; ++k) count += (inside[k] = in(c[k][0], c[k][1]));
    if (count == 0) return;
    auto ev = [&](int k) {
      const int n = (k + 1) % 4;
      return edge_vertex(c[k][0], c[k][1], c[n][0], c[n][1]);
    };
    if (count == 2 && inside[0] == inside[2]) {
      // Saddle: separated, one triangle at each inside corner.
      for (int k = 0; k < 4; ++k) {
        if (!inside[k]) continue;
        const int exit = ev(k), entry = ev((k + 3) % 4);
        out_.pieces.push_back({corner_vertex(c[k][0], c[k][1]), exit, entry});
        link(exit, entry);
      }
      return;
    }
    std::vector<int> piece;
    int pending_exit = -1, first_entry = -1;
    for (int k = 0; k < 4; ++k) {
      const int n = (k + 1) % 4;
      if (inside[k]) piece.push_back(corner_vertex(c[k][0], c[k][1]));
      if (inside[k] != inside[n]) {
        const int v = ev(k);
        piece.push_back(v);
        if (inside[k]) pending_exit = v;
        else if (pending_exit >= 0) link(pending_exit, v), pending_exit = -1;
        else first_entry = v;
      }
    }
    if (pending_exit >= 0) link(pending_exit, first_entry);
    out_.pieces.push_back(std::move(piece));
  }

  void link(int from, int to) { next_[from] = to; }

  void chain() {
    std::unordered_map<int, bool> seen;
    for (const auto& [start, unused] : next_) {
      (void)unused;
      if (seen.count(start)) continue;
      std::vector<int> loop;
      for (int v = start; !seen.count(v); v = next_.at(v)) {
        seen[v] = true;
        loop.push_back(v);
      }
      out_.area += polygon_area(out_.vertices, loop);
      out_.outlines.push_back(std::move(loop));
    }
  }

  const Grid& g_;
  std::uint8_t L_;
  const std::unordered_map<std::int64_t, Vec2>& refined_at_;
  LabelContours out_;
  std::unordered_map<std::int64_t, int> corners_, edges_;
  std::unordered_map<int, int> next_;
};

}  // namespace

double polygon_area(const std::vector<Vec2>& v, const std::vector<int>& loop) {
  if (loop.size() < 3) return 0;
  // Relative to the first vertex, to keep the products small.
  const Vec2 o = v[loop.front()];
  double twice = 0;
  for (std::size_t k = 1; k + 1 < loop.size(); ++k) {
    const Vec2 a = v[loop[k]] - o, b = v[loop[k + 1]] - o;
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * twice;
}

RegionContours region_contours(const RegionProblem& problem, const RegionResult& region,
                               const ContourOptions& options) {
  const RegionRequest& rq = problem.request();
  const View& v = problem.view();
  if (region.width != rq.width || region.height != rq.height || region.split != rq.split.has_value() ||
      region.view.x0 != v.x0 || region.view.y0 != v.y0 || region.view.x1 != v.x1 || region.view.y1 != v.y1 ||
      region.size() != static_cast<std::size_t>(rq.width) * rq.height)
    throw InputError("region_contours: the region was not rendered from this problem (size, view or split differ)");
  if (!(options.tolerance > 0) || !std::isfinite(options.tolerance))
    throw InputError("region_contours: the tolerance must be positive and finite");

  Grid g{rq.width, rq.height, rq.width + 2, rq.height + 2, v, region.codes()};
  const bool split = region.split;
  const double stop = options.tolerance * std::min(std::abs(v.x1 - v.x0), std::abs(v.y1 - v.y0));

  // Every edge between two pixel centres of different labels, bisected from
  // its first end (left or top) with that end's label.
  std::vector<Refined> jobs;
  for (int sj = 1; sj <= g.H; ++sj)
    for (int si = 1; si <= g.W; ++si)
      for (const bool vertical : {false, true}) {
        const Edge e{si, sj, vertical};
        const std::uint8_t b = g.label(e.bi(), e.bj());
        if (b != kPad && b != g.label(si, sj)) jobs.push_back({e, true, g.label(si, sj), {}});
      }
  auto run = [&](std::vector<Refined>& list) {
    parallel_for(list.size(), options.threads, [&](std::size_t k) {
      Refined& r = list[k];
      const Edge& e = r.edge;
      Vec2 a = g.centre(e.si, e.sj), b = g.centre(e.bi(), e.bj());
      std::uint8_t b_label = g.label(e.bi(), e.bj());
      if (!r.from_a) std::swap(a, b), b_label = g.label(e.si, e.sj);
      r.bracket = bisect(problem, split, a, b, r.label, b_label, stop);
    });
  };
  run(jobs);
  // Where the bracket ended at a third label, the far end's label needs its own.
  std::vector<Refined> second;
  for (const Refined& r : jobs) {
    const std::uint8_t b = g.label(r.edge.bi(), r.edge.bj());
    if (r.bracket.hi_label != b) second.push_back({r.edge, false, b, {}});
  }
  run(second);

  // The vertex of (edge, side): key 2 * edge id + 0 for the first end's label,
  // + 1 for the second end's.
  std::unordered_map<std::int64_t, Vec2> refined_at;
  refined_at.reserve(2 * jobs.size());
  auto vertex_of = [&](const Refined& r) {
    const Edge& e = r.edge;
    Vec2 a = g.centre(e.si, e.sj), b = g.centre(e.bi(), e.bj());
    if (!r.from_a) std::swap(a, b);
    return along(a, b, 0.5 * (r.bracket.lo + r.bracket.hi));
  };
  for (const Refined& r : jobs) {
    const Vec2 p = vertex_of(r);
    refined_at[2 * r.edge.id(g)] = p;
    if (r.bracket.hi_label == g.label(r.edge.bi(), r.edge.bj())) refined_at[2 * r.edge.id(g) + 1] = p;
  }
  for (const Refined& r : second) refined_at[2 * r.edge.id(g) + 1] = vertex_of(r);

  RegionContours out;
  out.view = v;
  out.split = split;
  out.bisections = jobs.size() + second.size();
  std::array<bool, 256> present{};
  for (std::uint8_t c : g.codes) present[c] = true;
  for (int L = 0; L < 256; ++L)
    if (present[L]) out.labels.push_back(LabelBuilder(g, static_cast<std::uint8_t>(L), refined_at).build());
  return out;
}

}  // namespace cmr
