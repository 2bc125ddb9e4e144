// Marching squares on a region's label map with certified refinement
// (algorithm and contracts: contour.hpp).
#include "bezierize/contour.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
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

/// The undecided band (contour.hpp): in every cell with an undecided gap on
/// one of its edges, the part of the cell that no label's piece covers: the
/// polygon of the cell's edge vertices in counter-clockwise order (each
/// label's piece is cut off by the chord between its own vertices). Its
/// outlines are the piece edges not shared by two pieces.
LabelContours undecided_band(const Grid& g, const std::unordered_map<std::int64_t, Vec2>& refined_at,
                             const std::unordered_map<std::int64_t, bool>& undecided_gap) {
  LabelContours band;
  band.label = kUndecidedBandLabel;
  if (undecided_gap.empty()) return band;
  std::map<std::pair<double, double>, int> index;  // one vertex per point
  auto vertex = [&](Vec2 p, bool refined) {
    auto [it, fresh] = index.try_emplace({p.x, p.y}, 0);
    if (fresh) {
      it->second = static_cast<int>(band.vertices.size());
      band.vertices.push_back(p);
      band.refined.push_back(refined);
    }
    return it->second;
  };
  std::map<std::pair<int, int>, int> directed;  // piece edges, counted
  for (int cj = 0; cj + 1 < g.SH; ++cj)
    for (int ci = 0; ci + 1 < g.SW; ++ci) {
      const std::array<std::array<int, 2>, 4> c = {{{ci, cj + 1}, {ci + 1, cj + 1}, {ci + 1, cj}, {ci, cj}}};
      bool gap = false;
      std::vector<int> piece;
      for (int k = 0; k < 4; ++k) {
        const auto& p = c[k];
        const auto& q = c[(k + 1) % 4];
        const std::uint8_t lp = g.label(p[0], p[1]), lq = g.label(q[0], q[1]);
        if (lp == lq) continue;
        if (lp == kPad || lq == kPad) {  // the view's edge: one vertex, as LabelBuilder puts it
          const int ri = lp == kPad ? q[0] : p[0], rj = lp == kPad ? q[1] : p[1];
          const int ai = lp == kPad ? p[0] : q[0], aj = lp == kPad ? p[1] : q[1];
          Vec2 at = g.centre(ri, rj);
          if (ai == 0) at.x = g.view.x0;
          if (ai == g.W + 1) at.x = g.view.x1;
          if (aj == 0) at.y = g.view.y1;
          if (aj == g.H + 1) at.y = g.view.y0;
          piece.push_back(vertex(at, false));
          continue;
        }
        Edge e;
        if (p[1] == q[1]) e = {std::min(p[0], q[0]), p[1], false};
        else e = {p[0], std::min(p[1], q[1]), true};
        const std::int64_t id = e.id(g);
        gap = gap || undecided_gap.count(id);
        // From p's side to q's: the vertex of p's label first.
        const bool p_first = p[0] == e.si && p[1] == e.sj;
        const int a = vertex(refined_at.at(2 * id + (p_first ? 0 : 1)), true);
        const int b = vertex(refined_at.at(2 * id + (p_first ? 1 : 0)), true);
        if (piece.empty() || piece.back() != a) piece.push_back(a);
        if (b != a) piece.push_back(b);
      }
      if (!gap) continue;
      if (piece.size() > 1 && piece.front() == piece.back()) piece.pop_back();
      if (piece.size() < 3) continue;
      for (std::size_t k = 0; k < piece.size(); ++k) ++directed[{piece[k], piece[(k + 1) % piece.size()]}];
      band.pieces.push_back(std::move(piece));
    }
  // Outline edges: those whose reverse is not a piece edge too.
  std::unordered_map<int, std::vector<int>> next;
  for (const auto& [edge, count] : directed)
    if (!directed.count({edge.second, edge.first}))
      for (int k = 0; k < count; ++k) next[edge.first].push_back(edge.second);
  for (auto& [start, targets] : next)
    while (!targets.empty()) {
      std::vector<int> loop{start};
      int v = targets.back();
      targets.pop_back();
      while (v != start) {
        loop.push_back(v);
        auto& out = next[v];
        if (out.empty()) break;  // not closed (cannot happen for pieces tiling a set); keep what there is
        const int w = out.back();
        out.pop_back();
        v = w;
      }
      band.area += polygon_area(band.vertices, loop);
      band.outlines.push_back(std::move(loop));
    }
  return band;
}

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
  // Edges whose first bracket ended at the undecided label (between two
  // decided labels): the stretch between their two vertices is undecided.
  const std::uint8_t undecided = split ? code(Split::undecided) : code(Direction::undecided);
  std::unordered_map<std::int64_t, bool> undecided_gap;
  for (const Refined& r : jobs)
    if (r.bracket.hi_label == undecided && r.label != undecided &&
        g.label(r.edge.bi(), r.edge.bj()) != undecided)
      undecided_gap[r.edge.id(g)] = true;

  RegionContours out;
  out.view = v;
  out.split = split;
  out.bisections = jobs.size() + second.size();
  std::array<bool, 256> present{};
  for (std::uint8_t c : g.codes) present[c] = true;
  for (int L = 0; L < 256; ++L)
    if (present[L]) out.labels.push_back(LabelBuilder(g, static_cast<std::uint8_t>(L), refined_at).build());
  out.band = undecided_band(g, refined_at, undecided_gap);
  return out;
}

}  // namespace cmr
