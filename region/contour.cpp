// Marching squares on a region's label map with certified refinement
// (algorithm and contracts: contour.hpp).
#include "region/contour.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

#include "spline/errors.hpp"
#include "spline/parallel.hpp"

namespace cmr {
namespace {

/// The sample grid: sample (si, sj), si = 0..W + 1, sj = 0..H + 1, sj = 0 the
/// top row; pixel (i, j) is sample (i + 1, j + 1); the samples of the outer
/// ring lie on the view's edge (contour.hpp).
struct Grid {
  int W = 0, H = 0, SW = 0, SH = 0;
  View view;
  std::vector<std::uint8_t> codes;  // of every sample, row-major over (si, sj)

  std::uint8_t label(int si, int sj) const { return codes[static_cast<std::size_t>(sample(si, sj))]; }
  Vec2 position(int si, int sj) const {
    const Vec2 c = pixel_center(view, W, H, std::clamp(si - 1, 0, W - 1), std::clamp(sj - 1, 0, H - 1));
    return {si == 0 ? view.x0 : si == W + 1 ? view.x1 : c.x, sj == 0 ? view.y1 : sj == H + 1 ? view.y0 : c.y};
  }
  std::int64_t sample(int si, int sj) const { return static_cast<std::int64_t>(sj) * SW + si; }
  bool ring(int si, int sj) const { return si == 0 || sj == 0 || si == W + 1 || sj == H + 1; }
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

/// The edge between two neighbouring samples, and whether p is its first end.
std::pair<Edge, bool> edge_between(int pi, int pj, int qi, int qj) {
  if (pj == qj) return {Edge{std::min(pi, qi), pj, false}, pi < qi};
  return {Edge{pi, std::min(pj, qj), true}, pj < qj};
}

struct Bracket {
  double lo = 0, hi = 1;
  std::uint8_t hi_label = 0;
};

Vec2 along(Vec2 a, Vec2 b, double t) { return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t}; }

/// Bisection from a (label L) towards b (label b_label != L); see contour.hpp.
Bracket bisect(const RegionProblem& problem, Vec2 a, Vec2 b, std::uint8_t L, std::uint8_t b_label, double stop) {
  const RegionRequest& rq = problem.request();
  Bracket r{0, 1, b_label};
  for (;;) {
    const Vec2 plo = along(a, b, r.lo), phi = along(a, b, r.hi);
    if (std::hypot(phi.x - plo.x, phi.y - plo.y) <= stop) break;
    const double mid = 0.5 * (r.lo + r.hi);
    if (!(r.lo < mid && mid < r.hi)) break;
    const std::uint8_t m = label_code(problem.classify(along(a, b, mid)), rq);
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

/// A point on a cell's boundary: a sample (a corner) or an edge vertex, with
/// the two labels its bracket separates (edge vertices only).
struct CellPoint {
  Vec2 p;
  bool refined = false;
  std::uint8_t from = 0, to = 0;  ///< the bracket's start label and end label
  /// A certified change from or to L lies within tolerance / 2 (contour.hpp):
  /// the owner's piece also holds other labels' vertices.
  bool refined_for(int L) const { return refined && (L == kUndecidedBandLabel || from == L || to == L); }
};

/// A refined vertex: where, and between which labels.
struct Vertex {
  Vec2 p;
  std::uint8_t from = 0, to = 0;
};

/// One cell (2x2 samples): its corners c0..c3 counter-clockwise from the
/// bottom-left, their labels, and the boundary walk's edge vertices.
struct Cell {
  std::array<CellPoint, 4> corner;
  std::array<std::uint8_t, 4> label{};
  /// Per edge k (c_k -> c_{k+1}): the vertex of c_k's label, then that of
  /// c_{k+1}'s (one point when they coincide); empty when the labels agree.
  std::array<std::vector<CellPoint>, 4> vertices;
  /// The label that owns the central polygon (the edge vertices in walk
  /// order), or -1 when it has under three points.
  int owner = -1;

  /// Every edge vertex in walk order.
  std::vector<CellPoint> central() const {
    std::vector<CellPoint> out;
    for (const auto& vs : vertices) out.insert(out.end(), vs.begin(), vs.end());
    return out;
  }
};

/// The pieces of label L in one cell (contour.hpp): the owner's piece is the
/// whole walk less the other labels' corners; any other label's, one piece
/// per run of consecutive corners with its label, from the vertex before the
/// run to the one after it.
std::vector<std::vector<CellPoint>> pieces_of(const Cell& c, int L) {
  std::vector<std::vector<CellPoint>> out;
  if (c.owner == L) {
    std::vector<CellPoint> piece;
    for (int k = 0; k < 4; ++k) {
      if (c.label[k] == L) piece.push_back(c.corner[k]);
      piece.insert(piece.end(), c.vertices[k].begin(), c.vertices[k].end());
    }
    out.push_back(std::move(piece));
    return out;
  }
  int start = -1;  // a corner of L whose predecessor is not L
  int count = 0;
  for (int k = 0; k < 4; ++k) {
    count += c.label[k] == L;
    if (c.label[k] == L && c.label[(k + 3) % 4] != L) start = k;
  }
  if (count == 4) {
    out.push_back({c.corner[0], c.corner[1], c.corner[2], c.corner[3]});
    return out;
  }
  if (start < 0) return out;
  for (int s = 0; s < 4; ++s) {
    const int k0 = (start + s) % 4;
    if (c.label[k0] != L || c.label[(k0 + 3) % 4] == L) continue;  // not a run's first corner
    std::vector<CellPoint> piece{c.vertices[(k0 + 3) % 4].back()};
    int k = k0;
    for (; c.label[k] == L; k = (k + 1) % 4) piece.push_back(c.corner[k]);
    piece.push_back(c.vertices[(k + 3) % 4].front());
    out.push_back(std::move(piece));
  }
  return out;
}

/// Outlines from pieces that tile a set: the directed piece edges whose
/// reverse is no piece's edge, chained into closed loops; their shoelace sum
/// is the set's area.
void chain_outlines(LabelContours& lc) {
  std::map<std::pair<int, int>, int> directed;
  for (const std::vector<int>& piece : lc.pieces)
    for (std::size_t k = 0; k < piece.size(); ++k) ++directed[{piece[k], piece[(k + 1) % piece.size()]}];
  std::map<int, std::vector<int>> next;
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
      lc.area += polygon_area(lc.vertices, loop);
      lc.outlines.push_back(std::move(loop));
    }
}

/// Builds one label's contours from its pieces, one vertex per point.
class LabelBuilder {
 public:
  explicit LabelBuilder(std::uint8_t L) : L_(L) { out_.label = L; }

  void add_piece(const std::vector<CellPoint>& points) {
    std::vector<int> piece;
    for (const CellPoint& q : points) {
      const int v = vertex(q);
      if (piece.empty() || piece.back() != v) piece.push_back(v);
    }
    while (piece.size() > 1 && piece.front() == piece.back()) piece.pop_back();
    if (piece.size() >= 3) out_.pieces.push_back(std::move(piece));
  }

  LabelContours build() {
    chain_outlines(out_);
    return std::move(out_);
  }

 private:
  int vertex(const CellPoint& q) {
    auto [it, fresh] = index_.try_emplace({q.p.x, q.p.y}, 0);
    if (fresh) {
      it->second = static_cast<int>(out_.vertices.size());
      out_.vertices.push_back(q.p);
      out_.refined.push_back(false);
    }
    if (q.refined_for(L_)) out_.refined[static_cast<std::size_t>(it->second)] = true;
    return it->second;
  }

  int L_;
  LabelContours out_;
  std::map<std::pair<double, double>, int> index_;
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

const char* RegionContours::label_name(std::uint8_t c) const {
  if (c == kUndecidedBandLabel) return kUndecidedBandName;
  RegionResult kind;
  kind.split = split;
  kind.alternating = alternating;
  kind.each_piece = each_piece;
  return kind.label_name(c);
}

RegionContours region_contours(const RegionProblem& problem, const RegionResult& region,
                               const ContourOptions& options) {
  const RegionRequest& rq = problem.request();
  const View& v = problem.view();
  const bool each_piece = rq.each_piece, alternating = !rq.splits.empty() && !each_piece;
  if (region.width != rq.width || region.height != rq.height || region.split != rq.split.has_value() ||
      region.each_piece != each_piece || region.alternating != alternating || region.view.x0 != v.x0 ||
      region.view.y0 != v.y0 || region.view.x1 != v.x1 || region.view.y1 != v.y1 ||
      region.size() != static_cast<std::size_t>(rq.width) * rq.height)
    throw InputError("region_contours: the region was not rendered from this problem (size, view or mode differ)");
  if (!(options.tolerance > 0) || !std::isfinite(options.tolerance))
    throw InputError("region_contours: the tolerance must be positive and finite");

  Grid g{rq.width, rq.height, rq.width + 2, rq.height + 2, v, {}};
  g.codes.assign(static_cast<std::size_t>(g.SW) * g.SH, 0);
  // The pixels' labels from the map; the ring's samples on the view's edge
  // classified here (the map has no sample there).
  const std::vector<std::uint8_t> pixels = region.codes();
  std::vector<std::pair<int, int>> ring;
  for (int sj = 0; sj < g.SH; ++sj)
    for (int si = 0; si < g.SW; ++si) {
      if (g.ring(si, sj)) ring.emplace_back(si, sj);
      else g.codes[g.sample(si, sj)] = pixels[static_cast<std::size_t>(sj - 1) * g.W + (si - 1)];
    }
  parallel_for(ring.size(), options.threads, [&](std::size_t k) {
    const auto [si, sj] = ring[k];
    g.codes[g.sample(si, sj)] = label_code(problem.classify(g.position(si, sj)), rq);
  });
  const double stop = options.tolerance * std::min(std::abs(v.x1 - v.x0), std::abs(v.y1 - v.y0));

  // Every edge between two samples of different labels, bisected from its
  // first end (left or top) with that end's label.
  std::vector<Refined> jobs;
  for (int sj = 0; sj < g.SH; ++sj)
    for (int si = 0; si < g.SW; ++si)
      for (const bool vertical : {false, true}) {
        const Edge e{si, sj, vertical};
        if (e.bi() >= g.SW || e.bj() >= g.SH) continue;
        if (g.label(e.bi(), e.bj()) != g.label(si, sj)) jobs.push_back({e, true, g.label(si, sj), {}});
      }
  auto run = [&](std::vector<Refined>& list) {
    parallel_for(list.size(), options.threads, [&](std::size_t k) {
      Refined& r = list[k];
      const Edge& e = r.edge;
      Vec2 a = g.position(e.si, e.sj), b = g.position(e.bi(), e.bj());
      std::uint8_t b_label = g.label(e.bi(), e.bj());
      if (!r.from_a) std::swap(a, b), b_label = g.label(e.si, e.sj);
      r.bracket = bisect(problem, a, b, r.label, b_label, stop);
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
  std::map<std::int64_t, Vertex> refined_at;
  auto vertex_of = [&](const Refined& r) {
    const Edge& e = r.edge;
    Vec2 a = g.position(e.si, e.sj), b = g.position(e.bi(), e.bj());
    if (!r.from_a) std::swap(a, b);
    return along(a, b, 0.5 * (r.bracket.lo + r.bracket.hi));
  };
  for (const Refined& r : jobs) {
    const Vertex p{vertex_of(r), r.label, r.bracket.hi_label};
    refined_at[2 * r.edge.id(g)] = p;
    if (r.bracket.hi_label == g.label(r.edge.bi(), r.edge.bj())) refined_at[2 * r.edge.id(g) + 1] = p;
  }
  for (const Refined& r : second) refined_at[2 * r.edge.id(g) + 1] = {vertex_of(r), r.label, r.bracket.hi_label};
  // Edges whose first bracket ended at the undecided label (between two
  // decided labels): the stretch between their two vertices is undecided.
  const std::uint8_t undecided = static_cast<std::uint8_t>(region.label_codes() - 1);
  std::map<std::int64_t, bool> undecided_gap;
  for (const Refined& r : jobs)
    if (r.bracket.hi_label == undecided && r.label != undecided && g.label(r.edge.bi(), r.edge.bj()) != undecided)
      undecided_gap[r.edge.id(g)] = true;

  // The cells, their edge vertices and the owners of their central polygons.
  std::vector<Cell> cells;
  cells.reserve(static_cast<std::size_t>(g.SW - 1) * (g.SH - 1));
  std::vector<std::size_t> owned;  // cells whose owner a classification decides
  for (int cj = 0; cj + 1 < g.SH; ++cj)
    for (int ci = 0; ci + 1 < g.SW; ++ci) {
      const std::array<std::array<int, 2>, 4> at = {{{ci, cj + 1}, {ci + 1, cj + 1}, {ci + 1, cj}, {ci, cj}}};
      Cell c;
      bool gap = false;
      for (int k = 0; k < 4; ++k) {
        c.corner[k] = {g.position(at[k][0], at[k][1]), false};
        c.label[k] = g.label(at[k][0], at[k][1]);
      }
      for (int k = 0; k < 4; ++k) {
        const int n = (k + 1) % 4;
        if (c.label[k] == c.label[n]) continue;
        const auto [e, k_first] = edge_between(at[k][0], at[k][1], at[n][0], at[n][1]);
        const std::int64_t id = e.id(g);
        gap = gap || undecided_gap.count(id);
        const Vertex a = refined_at.at(2 * id + (k_first ? 0 : 1)), b = refined_at.at(2 * id + (k_first ? 1 : 0));
        c.vertices[k].push_back({a.p, true, a.from, a.to});
        if (b.p.x != a.p.x || b.p.y != a.p.y) c.vertices[k].push_back({b.p, true, b.from, b.to});
      }
      std::vector<CellPoint> mid = c.central();
      if (!mid.empty() && mid.front().p.x == mid.back().p.x && mid.front().p.y == mid.back().p.y) mid.pop_back();
      if (mid.size() >= 3) {
        if (gap) c.owner = kUndecidedBandLabel;
        else owned.push_back(cells.size());
      }
      cells.push_back(std::move(c));
    }
  // The central polygon's owner: the label at its centroid (of its points);
  // an undecided centroid where no corner is undecided is the band's.
  parallel_for(owned.size(), options.threads, [&](std::size_t k) {
    Cell& c = cells[owned[k]];
    const std::vector<CellPoint> mid = c.central();
    Vec2 sum{0, 0};
    for (const CellPoint& q : mid) sum = sum + q.p;
    const double n = static_cast<double>(mid.size());
    const std::uint8_t l = label_code(problem.classify({sum.x / n, sum.y / n}), rq);
    const bool corner_undecided = std::find(c.label.begin(), c.label.end(), undecided) != c.label.end();
    c.owner = l == undecided && !corner_undecided ? kUndecidedBandLabel : l;
  });

  RegionContours out;
  out.view = v;
  out.split = region.split;
  out.alternating = alternating;
  out.each_piece = each_piece;
  out.bisections = jobs.size() + second.size();
  std::array<bool, 256> present{};
  for (std::uint8_t c : g.codes) present[c] = true;
  for (const Cell& c : cells)
    if (c.owner >= 0 && c.owner != kUndecidedBandLabel) present[static_cast<std::size_t>(c.owner)] = true;
  for (int L = 0; L < 256; ++L) {
    if (!present[L] || L == kUndecidedBandLabel) continue;
    LabelBuilder b(static_cast<std::uint8_t>(L));
    for (const Cell& c : cells)
      for (const std::vector<CellPoint>& piece : pieces_of(c, L)) b.add_piece(piece);
    out.labels.push_back(b.build());
  }
  LabelBuilder band(kUndecidedBandLabel);
  for (const Cell& c : cells)
    for (const std::vector<CellPoint>& piece : pieces_of(c, kUndecidedBandLabel)) band.add_piece(piece);
  out.band = band.build();
  return out;
}

}  // namespace cmr
