// The designspace fix of g1-between-masters (report/interpolation.hpp):
// g1_least_move, the exact gate's least move over every grid position of
// one master's handles, the :DEG families (g1_between_fix,
// ratio_turn_fixes, parallel_turn_fix), and fix_g1_between_masters, which
// reads the masters, picks the master and re-judges the result exactly.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <numbers>
#include <numeric>
#include <set>
#include <tuple>

#include "io/ufo.hpp"
#include "report/interpolation.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"

namespace cmr::report {

namespace {

/// Every point of both masters an integer below `limit` in magnitude: font
/// units a double and a long long hold exactly (the grid moves' domain).
bool grid_points(const Vec2 node[2], const Vec2 in_handle[2], const Vec2 out_handle[2], double limit) {
  for (int m = 0; m < 2; ++m)
    for (const Vec2 p : {node[m], in_handle[m], out_handle[m]})
      if (!(std::abs(p.x) < limit && std::abs(p.y) < limit) || p.x != std::floor(p.x) || p.y != std::floor(p.y))
        return false;
  return true;
}

}  // namespace

std::optional<G1NodeFix> g1_between_fix(const Vec2 node[2], const Vec2 in_handle[2], const Vec2 out_handle[2],
                                        bool in_fixed, bool out_fixed) {
  using I = long long;
  if (!grid_points(node, in_handle, out_handle, 1e15)) return std::nullopt;  // room for products
  // u = alpha g, v = beta g at each master (g primitive), or nullopt.
  struct Split {
    I gx, gy, alpha, beta;
  };
  auto split = [&](int m) -> std::optional<Split> {
    const I ux = static_cast<I>(node[m].x - in_handle[m].x), uy = static_cast<I>(node[m].y - in_handle[m].y);
    const I vx = static_cast<I>(out_handle[m].x - node[m].x), vy = static_cast<I>(out_handle[m].y - node[m].y);
    if ((ux == 0 && uy == 0) || (vx == 0 && vy == 0)) return std::nullopt;
    const I gv = std::gcd(std::abs(vx), std::abs(vy)), gu = std::gcd(std::abs(ux), std::abs(uy));
    const I gx = vx / gv, gy = vy / gv;
    if (ux / gu != gx || uy / gu != gy) return std::nullopt;  // not exactly G1 here
    return Split{gx, gy, gu, gv};
  };
  const std::optional<Split> a = split(0), b = split(1);
  if (!a || !b) return std::nullopt;
  G1NodeFix out{in_handle[0], out_handle[0], 0.0};
  const I cross = a->gx * b->gy - a->gy * b->gx;
  if (cross == 0) {
    if (a->gx * b->gx + a->gy * b->gy < 0) return std::nullopt;  // opposite directions: the node reverses
    return out;                                                  // the same direction at both: G1 throughout
  }
  const I common = std::gcd(b->alpha, b->beta), p = b->alpha / common, q = b->beta / common;
  auto cost = [&](I k) { return std::llabs(p * k - a->alpha) + std::llabs(q * k - a->beta); };
  I best = 0;
  if (in_fixed || out_fixed) {
    // A side that is a line keeps its length: k is the one that side has
    // (alpha = p k, or beta = q k), when it is an integer.
    const I fixed = in_fixed ? a->alpha : a->beta, unit = in_fixed ? p : q;
    if (fixed % unit != 0) return std::nullopt;
    best = fixed / unit;
    if (in_fixed && out_fixed && q * best != a->beta) return std::nullopt;
  } else {
    for (const I k0 : {a->alpha / p, a->beta / q})
      for (const I k : {k0, k0 + 1})
        if (k >= 1 && (best == 0 || cost(k) < cost(best))) best = k;
  }
  const double len = std::hypot(static_cast<double>(a->gx), static_cast<double>(a->gy));
  const Vec2 g{static_cast<double>(a->gx), static_cast<double>(a->gy)};
  out.in_handle = node[0] - static_cast<double>(p * best) * g;
  out.out_handle = node[0] + static_cast<double>(q * best) * g;
  out.distance = static_cast<double>(cost(best)) * len;
  return out;
}

std::optional<G1NodeFix> parallel_turn_fix(const Vec2 node[2], const Vec2 in_handle[2], const Vec2 out_handle[2]) {
  using I = long long;
  if (!grid_points(node, in_handle, out_handle, 1e15)) return std::nullopt;
  // Each handle on the ray of the other master's tangent from the node, at
  // the grid point of it nearest where it is: N -/+ j w, w the tangent's
  // primitive integer direction, j >= 1.
  auto on_ray = [&](Vec2 tangent, Vec2 handle, double side) -> std::optional<Vec2> {
    if (tangent == Vec2(0.0)) return std::nullopt;
    const double g = static_cast<double>(std::gcd(static_cast<I>(std::abs(tangent.x)), static_cast<I>(std::abs(tangent.y))));
    const Vec2 w = side * tangent / g;
    const double j = std::max(1.0, std::nearbyint(dot(handle - node[0], w) / dot(w, w)));
    return node[0] + j * w;
  };
  const std::optional<Vec2> in = on_ray(node[1] - in_handle[1], in_handle[0], -1);
  const std::optional<Vec2> out = on_ray(out_handle[1] - node[1], out_handle[0], 1);
  if (!in || !out) return std::nullopt;
  return G1NodeFix{*in, *out,
                   std::hypot(in->x - in_handle[0].x, in->y - in_handle[0].y) +
                       std::hypot(out->x - out_handle[0].x, out->y - out_handle[0].y)};
}

namespace {

// g1_least_move's integer vectors (|coordinates| < 1e9: products fit 64 bits, sums of two 128).
using Int = long long;
__extension__ using Wide = __int128;  // GCC's, named once (-Wpedantic)
struct IVec {
  Int x = 0, y = 0;
  bool operator==(const IVec&) const = default;
};
IVec ivec(Vec2 v) { return {static_cast<Int>(v.x), static_cast<Int>(v.y)}; }
Vec2 vec2(IVec v) { return {static_cast<double>(v.x), static_cast<double>(v.y)}; }
Wide icross(IVec a, IVec b) { return static_cast<Wide>(a.x) * b.y - static_cast<Wide>(a.y) * b.x; }
Wide idot(IVec a, IVec b) { return static_cast<Wide>(a.x) * b.x + static_cast<Wide>(a.y) * b.y; }
double gap(IVec a, IVec b) { return std::hypot(static_cast<double>(a.x - b.x), static_cast<double>(a.y - b.y)); }
bool on_grid(Vec2 p) { return std::abs(p.x) < 1e9 && std::abs(p.y) < 1e9 && p.x == std::floor(p.x) && p.y == std::floor(p.y); }

// (u, v) times the least 2^s (s <= 30) that makes every coordinate an
// integer below 2^40 in magnitude (exact: a power of two scales a double
// exactly); nullopt: none.
std::optional<std::array<IVec, 2>> dyadic_scaled(Vec2 u, Vec2 v) {
  for (int s = 0; s <= 30; ++s) {
    const double f = std::ldexp(1.0, s);
    const Vec2 a = f * u, b = f * v;
    bool whole = true;
    for (const double x : {a.x, a.y, b.x, b.y})
      if (!(std::abs(x) < 0x1p40) || x != std::floor(x)) whole = false;
    if (whole) return std::array<IVec, 2>{ivec(a), ivec(b)};
  }
  return std::nullopt;
}

// A node's requirement of its tangents at m: against each judged neighbour,
// its tangent u' and ratio v' = (num / den) u' (reduced, positive).
struct TangentNeeds {
  struct Other {
    IVec u;
    Int num, den;
  };
  std::vector<Other> others;
  bool keep_g1 = true;
};

// What a node's other side may be, given one side ("known": u when
// known_in, else v), by the header's rule: against a neighbour whose
// tangent crosses `known`, exactly known * r (or known / r): a point; along
// every neighbour's tangent, any positive multiple of known's primitive
// direction: a ray (j w, j >= 1). none: refused.
struct Sides {
  enum class Kind { none, point, ray } kind = Kind::none;
  IVec at{};  ///< the point, or the ray's step w
};
Sides sides(const TangentNeeds& req, IVec known, bool known_in) {
  if (known == IVec{}) return {};
  bool ratio = false;
  Int num = 0, den = 0;
  for (const TangentNeeds::Other& o : req.others) {
    if (icross(known, o.u) == 0) {
      if (idot(known, o.u) < 0) return {};  // the tangent would reverse between the masters
      continue;
    }
    const Int n = known_in ? o.num : o.den, d = known_in ? o.den : o.num;
    if (ratio && static_cast<Wide>(num) * d != static_cast<Wide>(n) * den) return {};
    ratio = true, num = n, den = d;
  }
  if (ratio) {
    const Wide x = static_cast<Wide>(known.x) * num, y = static_cast<Wide>(known.y) * num;
    if (x % den != 0 || y % den != 0) return {};  // off the grid
    return {Sides::Kind::point, {static_cast<Int>(x / den), static_cast<Int>(y / den)}};
  }
  const Int g = std::gcd(std::llabs(known.x), std::llabs(known.y));
  return {Sides::Kind::ray, {known.x / g, known.y / g}};
}

// The member of `s` nearest `old` (or `old` itself when that side is a
// line, `fixed`), with its distance; nullopt: none.
std::optional<std::pair<IVec, double>> nearest(const Sides& s, IVec old, bool fixed) {
  if (s.kind == Sides::Kind::none) return std::nullopt;
  if (s.kind == Sides::Kind::point) {
    if (fixed) return s.at == old ? std::optional{std::pair{old, 0.0}} : std::nullopt;
    return std::pair{s.at, gap(s.at, old)};
  }
  const IVec w = s.at;
  if (fixed) return icross(old, w) == 0 && idot(old, w) > 0 ? std::optional{std::pair{old, 0.0}} : std::nullopt;
  const double j = static_cast<double>(idot(old, w)) / static_cast<double>(idot(w, w));
  std::optional<std::pair<IVec, double>> best;
  for (const double k : {std::floor(j), std::ceil(j)}) {
    const Int n = std::max<Int>(1, static_cast<Int>(k));
    const IVec t{n * w.x, n * w.y};
    if (!best || gap(t, old) < best->second) best = std::pair{t, gap(t, old)};
  }
  return best;
}

}  // namespace

std::optional<G1LeastMove> g1_least_move(const std::vector<G1NodeRule>& rules, bool closed, double reach) {
  const std::size_t k = rules.size();
  if (k == 0) return std::nullopt;
  std::vector<TangentNeeds> req(k);
  for (std::size_t i = 0; i < k; ++i) {
    const G1NodeRule& r = rules[i];
    if (!on_grid(r.node) || !on_grid(r.in_handle) || !on_grid(r.out_handle)) return std::nullopt;
    req[i].keep_g1 = r.keep_g1 || !r.others.empty();
    for (const auto& [u, v] : r.others) {
      // The neighbour's points need not be on the grid (only m's move onto
      // it): u' and v' times 2^s, the least power of two that makes all four
      // coordinates integers (exact for doubles with at most 30 bits after
      // the point), give the same direction and ratio.
      const std::optional<std::array<IVec, 2>> scaled = dyadic_scaled(u, v);
      if (!scaled) return std::nullopt;
      const IVec iu = (*scaled)[0], iv = (*scaled)[1];
      if (iu == IVec{} || iv == IVec{} || icross(iu, iv) != 0 || idot(iu, iv) <= 0) return std::nullopt;
      const Int a = std::gcd(std::llabs(iu.x), std::llabs(iu.y)), b = std::gcd(std::llabs(iv.x), std::llabs(iv.y));
      const Int c = std::gcd(a, b);
      req[i].others.push_back({iu, b / c, a / c});  // v' = (b / a) u'
    }
    // A run: each node's outgoing handle is the next one's incoming (a shared point, never a line's end).
    if (i + 1 < k || closed) {
      const G1NodeRule& next = rules[(i + 1) % k];
      if (r.out_handle != next.in_handle || r.out_fixed || next.in_fixed) return std::nullopt;
    }
  }
  if (closed && k < 2) return std::nullopt;
  // In a run every node has a rule (a node without one leaves its handles
  // free: the caller does not link it).
  if (k > 1)
    for (const TangentNeeds& r : req)
      if (r.others.empty() && !r.keep_g1) return std::nullopt;
  // The handles h_0..h_k: h_{i-1} and h_i are node i's (counted from 1);
  // h_k is h_0 on a closed run. Their positions now:
  std::vector<IVec> old(k + 1);
  for (std::size_t i = 0; i < k; ++i) old[i] = ivec(rules[i].in_handle);
  old[k] = ivec(rules[k - 1].out_handle);
  std::vector<IVec> h(k + 1), best_h;
  double best = std::numeric_limits<double>::infinity();
  bool greedy = true;
  // Node i + 1 (0-based i) given h_i: h_{i+1} is a point or a ray; on the
  // last node of an open run the nearest member, on a closed run h_0 must
  // be a member; in between, every member the budget leaves (branch and
  // bound: every move is >= 0, so a partial total >= best ends the branch).
  std::function<void(std::size_t, double)> walk = [&](std::size_t i, double spent) {
    const IVec node = ivec(rules[i].node);
    const Sides s = sides(req[i], IVec{node.x - h[i].x, node.y - h[i].y}, true);
    const bool unconstrained = req[i].others.empty() && !req[i].keep_g1;
    if (i + 1 == k) {
      if (closed) {
        const IVec v{h[0].x - node.x, h[0].y - node.y};
        if (unconstrained || (s.kind == Sides::Kind::point && s.at == v) ||
            (s.kind == Sides::Kind::ray && icross(v, s.at) == 0 && idot(v, s.at) > 0)) {
          h[k] = h[0];
          if (spent < best) best = spent, best_h = h;
        }
        return;
      }
      const IVec v_old{old[k].x - node.x, old[k].y - node.y};
      const auto last = unconstrained ? std::optional{std::pair{v_old, 0.0}} : nearest(s, v_old, rules[i].out_fixed);
      if (last && spent + last->second < best) {
        h[k] = IVec{node.x + last->first.x, node.y + last->first.y};
        best = spent + last->second, best_h = h;
      }
      return;
    }
    auto next = [&](IVec at) {
      const double cost = spent + gap(at, old[i + 1]);
      if (cost >= best) return;
      h[i + 1] = at;
      walk(i + 1, cost);
    };
    if (s.kind == Sides::Kind::point) {
      next(IVec{node.x + s.at.x, node.y + s.at.y});
    } else if (s.kind == Sides::Kind::ray) {
      // j w with |node + j w - old| < best - spent: j within that reach of old's projection.
      const IVec w = s.at;
      const IVec rel{old[i + 1].x - node.x, old[i + 1].y - node.y};
      const double wl = std::sqrt(static_cast<double>(idot(w, w)));
      if (greedy) {  // the first pass: the nearest member only, for a first bound
        const auto n = nearest(s, rel, false);
        if (n) next(IVec{node.x + n->first.x, node.y + n->first.y});
        return;
      }
      const double mid = static_cast<double>(idot(rel, w)) / (wl * wl), room = (std::min(best, reach) - spent) / wl;
      const double lo = std::max(1.0, std::floor(mid - room)), hi = std::ceil(mid + room);
      for (double j = lo; j <= hi; ++j) next(IVec{node.x + static_cast<Int>(j) * w.x, node.y + static_cast<Int>(j) * w.y});
    }
  };
  if (k == 1 && !closed && rules[0].out_fixed && !rules[0].in_fixed) {  // the outgoing side a line: u follows
    const IVec node = ivec(rules[0].node), v{old[1].x - node.x, old[1].y - node.y};
    const auto a = nearest(sides(req[0], v, false), IVec{node.x - old[0].x, node.y - old[0].y}, false);
    if (!a || !(a->second <= reach)) return std::nullopt;
    return G1LeastMove{{{vec2(IVec{node.x - a->first.x, node.y - a->first.y}), rules[0].out_handle, a->second}}, a->second};
  }
  // h_0 in square rings around where it is (a line's end stays): every
  // point of ring r is at least r away, so once r reaches the best total no
  // later h_0 is cheaper. Two passes: the first takes each ray's nearest
  // member (a first bound, quickly); the second every member within the
  // bound (or `reach`).
  const Int limit = rules[0].in_fixed ? 0 : static_cast<Int>(std::max(0.0, std::floor(reach)));
  for (const bool pass : {true, false}) {
    greedy = pass;
    // The first pass within 64 units only: where it finds nothing, the
    // second is the search (bounded by `reach`).
    const Int rings = pass ? std::min<Int>(limit, 64) : limit;
    for (Int r = 0; r <= rings && static_cast<double>(r) < best; ++r) {
      auto visit = [&](Int dx, Int dy) {
        h[0] = IVec{old[0].x + dx, old[0].y + dy};
        const double c = gap(h[0], old[0]);
        if (c < best) walk(0, c);
      };
      if (r == 0) {
        visit(0, 0);
        continue;
      }
      for (Int d = -r; d <= r; ++d) visit(d, -r), visit(d, r);
      for (Int d = -r + 1; d <= r - 1; ++d) visit(-r, d), visit(r, d);
    }
  }
  if (!(best <= reach) || best_h.empty()) return std::nullopt;
  G1LeastMove out;
  out.distance = best;
  for (std::size_t i = 0; i < k; ++i) {
    const double moved = (i == 0 ? gap(best_h[0], old[0]) : 0.0) + (closed && i + 1 == k ? 0.0 : gap(best_h[i + 1], old[i + 1]));
    out.nodes.push_back({vec2(best_h[i]), vec2(best_h[i + 1]), moved});
  }
  return out;
}

namespace {

/// g1-between-masters:DEG's gentlest family of moves: master [0]'s handles
/// kept on their own tangents (multiples a, b of the tangents' primitive
/// integer directions: on the grid), their lengths near master [1]'s ratio
/// (b = a / r or a = b r, rounded both ways; a line's side keeps its
/// length), cheapest first. Whether the turn then stays within DEG between
/// the masters is the caller's exact judgement, candidate by candidate.
std::vector<G1NodeFix> ratio_turn_fixes(const Vec2 node[2], const Vec2 in_handle[2], const Vec2 out_handle[2],
                                        bool in_fixed, bool out_fixed) {
  using I = long long;
  if (!grid_points(node, in_handle, out_handle, 1e9)) return {};  // lengths' multiples stay small integers
  const Vec2 um = node[0] - in_handle[0], vm = out_handle[0] - node[0];
  const Vec2 uo = node[1] - in_handle[1], vo = out_handle[1] - node[1];
  if (um == Vec2(0.0) || vm == Vec2(0.0) || uo == Vec2(0.0) || vo == Vec2(0.0)) return {};
  const I gu = std::gcd(static_cast<I>(std::abs(um.x)), static_cast<I>(std::abs(um.y)));
  const I gv = std::gcd(static_cast<I>(std::abs(vm.x)), static_cast<I>(std::abs(vm.y)));
  const Vec2 wu = um / static_cast<double>(gu), wv = vm / static_cast<double>(gv);  // master 0's own directions
  // a / b that gives master 1's length ratio |uo| : |vo| along wu, wv.
  const double r = std::hypot(uo.x, uo.y) / std::hypot(vo.x, vo.y) * std::hypot(wv.x, wv.y) / std::hypot(wu.x, wu.y);
  std::vector<G1NodeFix> out;
  std::set<std::pair<I, I>> seen;
  auto add = [&](I a, I b) {
    if (a < 1 || b < 1 || (in_fixed && a != gu) || (out_fixed && b != gv) || !seen.insert({a, b}).second) return;
    const Vec2 in = node[0] - static_cast<double>(a) * wu, o = node[0] + static_cast<double>(b) * wv;
    out.push_back({in, o, std::hypot(in.x - in_handle[0].x, in.y - in_handle[0].y) + std::hypot(o.x - out_handle[0].x, o.y - out_handle[0].y)});
  };
  const I reach = 2 * std::max(gu, gv) + 4;
  for (I a = 1; a <= reach; ++a) {
    const double b = static_cast<double>(a) / r;
    for (const I k : {static_cast<I>(std::floor(b)), static_cast<I>(std::ceil(b))}) add(a, k);
  }
  for (I b = 1; b <= reach; ++b) {
    const double a = static_cast<double>(b) * r;
    for (const I k : {static_cast<I>(std::floor(a)), static_cast<I>(std::ceil(a))}) add(k, b);
  }
  std::sort(out.begin(), out.end(), [](const G1NodeFix& x, const G1NodeFix& y) { return x.distance < y.distance; });
  return out;
}

}  // namespace

MastersG1Fix fix_g1_between_masters(const std::string& path, const std::string& glyph, double turn_degrees) {
  const Rational T(turn_degrees > 0 ? std::tan(turn_degrees * std::numbers::pi / 180) : 0.0);
  const import::Designspace ds = import::read_designspace(path);
  std::vector<const import::Designspace::Source*> sources;
  for (const auto& src : ds.sources)
    if (src.layer.empty()) sources.push_back(&src);
  const std::size_t n = sources.size();
  if (n < 2)
    throw InputFieldError(path + ": cmr fix " + field("require") +
                          " g1-between-masters takes a designspace of two masters or more (" +
                     std::to_string(n) + " here)");
  import::GlyphSelection which;
  which.names = {glyph};
  // The pieces: pairs of adjacent masters (io/masters.hpp), by index.
  std::vector<std::pair<std::size_t, std::size_t>> pieces;
  {
    const import::Masters masters = import::read_masters(path, which);
    auto index_of = [&](const std::string& name) {
      for (std::size_t k = 0; k < n; ++k)
        if (sources[k]->name == name) return k;
      throw InputError(path + ": two sources named '" + name + "'?");
    };
    for (const auto& p : masters.pieces) {
      const std::pair<std::size_t, std::size_t> ab{index_of(p->master_a), index_of(p->master_b)};
      if (std::find(pieces.begin(), pieces.end(), ab) == pieces.end()) pieces.push_back(ab);
    }
  }
  std::vector<import::Glyph> g(n);
  for (std::size_t m = 0; m < n; ++m) {
    const import::Font f = import::read_ufo(sources[m]->path, which);
    if (f.glyphs.empty()) throw InputError(path + ": no glyph '" + glyph + "' in " + sources[m]->name);
    g[m] = f.glyphs.front();
    if (!g[m].error.empty()) throw InputError(path + ": " + g[m].error);
    if (g[m].contours.size() != g[0].contours.size()) throw InputError(path + ": " + glyph + ": incompatible masters");
  }
  // A node with a handle or a line on each side: its position, handles (on a line's side: the line's other
  // end, which stays), and their source points, per master; and whether it is marked smooth there.
  struct Node {
    int contour = 0, node = 0, in = 0, out = 0;  // Contour::index and source points
    std::string name;
    std::vector<Vec2> p, h_in, h_out;
    std::vector<bool> smooth;
    bool in_line = false, out_line = false;  // that side is a line: its end never moves
  };
  std::vector<Node> nodes;
  for (std::size_t c = 0; c < g[0].contours.size(); ++c) {
    const import::Contour& a = g[0].contours[c];
    for (std::size_t m = 1; m < n; ++m) {
      const import::Contour& b = g[m].contours[c];
      if (a.font_point != b.font_point || a.node != b.node || a.spline.degree() != b.spline.degree())
        throw InputError(path + ": " + glyph + ": incompatible masters (contour " + std::to_string(a.index) + ")");
    }
    const int count = static_cast<int>(a.node.size());
    // The point that gives a node's tangent on one side (step -1 or +1): its handle, or where that side is a
    // line (the next point a node, or a line's added inner point) the line's other end, a node that stays.
    auto side = [&](int i, int step, bool& line) {
      const int j = (i + step + count) % count;
      line = a.node[j] || a.font_point[j] < 0;
      if (!line) return j;
      int k = j;
      while (!a.node[k] && k != i) k = (k + step + count) % count;
      return k;
    };
    for (int i = 0; i < count; ++i) {
      if (!a.node[i] || a.font_point[i] < 0 || (!a.spline.closed() && (i == 0 || i == count - 1))) continue;
      bool in_line = false, out_line = false;
      const int prev = side(i, -1, in_line), next = side(i, 1, out_line);
      if (prev == i || next == i || a.font_point[prev] < 0 || a.font_point[next] < 0) continue;
      Node node{a.index, a.font_point[i], a.font_point[prev], a.font_point[next], a.point_names[i], {}, {}, {}, {},
                in_line, out_line};
      for (std::size_t m = 0; m < n; ++m) {
        const auto& marks = g[m].point_smooth;
        const int fp = a.font_point[i];
        node.smooth.push_back(a.index < static_cast<int>(marks.size()) && fp < static_cast<int>(marks[a.index].size()) &&
                              marks[a.index][fp]);
        const std::vector<Vec2>& pts = g[m].contours[c].spline.points();
        node.p.push_back(pts[i]);
        node.h_in.push_back(pts[prev]);
        node.h_out.push_back(pts[next]);
      }
      if (std::any_of(node.smooth.begin(), node.smooth.end(), [](bool b) { return b; })) nodes.push_back(node);
    }
  }
  auto tangents_of = [](const Node& k, std::size_t a, std::size_t b) {
    const Vec2 u0 = k.p[a] - k.h_in[a], u1 = k.p[b] - k.h_in[b], v0 = k.h_out[a] - k.p[a], v1 = k.h_out[b] - k.p[b];
    return NodeTangents{Rational(u0.x), Rational(u0.y), Rational(u1.x), Rational(u1.y),
                        Rational(v0.x), Rational(v0.y), Rational(v1.x), Rational(v1.y)};
  };
  // Judged on the piece a-b: marked smooth at both masters and exactly G1 at both (as the gate judges).
  auto judged = [&](const Node& k, std::size_t a, std::size_t b) {
    if (!k.smooth[a] || !k.smooth[b]) return false;
    const NodeTangents t = tangents_of(k, a, b);
    return g1_at(t.u0x, t.u0y, t.v0x, t.v0y, T) && g1_at(t.u1x, t.u1y, t.v1x, t.v1y, T);
  };
  auto kink = [&](const Node& k, std::size_t a, std::size_t b) {
    return judged(k, a, b) && !g1_between(tangents_of(k, a, b), T).holds;
  };
  auto kinks = [&](const std::vector<Node>& all) {
    int count = 0;
    for (const Node& k : all)
      for (const auto& [a, b] : pieces) count += kink(k, a, b) ? 1 : 0;
    return count;
  };
  // Master m's handles move: every kinked node must lie on pieces with m only.
  MastersG1Fix best;
  best.distance = -1;
  std::string unfixable;
  // Records a node's new handles at m as edits of its source points (a
  // shared point once; a point given two places is a conflict: false).
  auto record = [&](MastersG1Fix& fix, const Node& k, std::size_t m, Vec2 in, Vec2 out) {
    for (const auto& [from, to, fp, line] : {std::tuple{k.h_in[m], in, k.in, k.in_line}, std::tuple{k.h_out[m], out, k.out, k.out_line}}) {
      if (from == to) continue;
      if (line) return false;  // a line's end never moves
      bool seen = false;
      for (const import::PointEdit& e : fix.edits)
        if (e.contour == k.contour && e.point == fp) {
          if (e.x != to.x || e.y != to.y) return false;
          seen = true;
        }
      if (seen) continue;
      std::string name = glyph;
      name.append("/c").append(std::to_string(k.contour)).append("/p").append(std::to_string(fp));
      fix.moves.push_back({name, from, to, std::hypot(to.x - from.x, to.y - from.y)});
      fix.edits.push_back({k.contour, fp, to.x, to.y});
    }
    return true;
  };
  // The nodes with every edit of master m applied (a handle shared by two
  // nodes moves for both): what the written .glif holds, re-judged.
  auto applied = [&](const MastersG1Fix& fix, std::size_t m) {
    std::vector<Node> out = nodes;
    for (Node& k : out)
      for (const import::PointEdit& e : fix.edits) {
        if (e.contour != k.contour) continue;
        if (!k.in_line && e.point == k.in) k.h_in[m] = Vec2{e.x, e.y};
        if (!k.out_line && e.point == k.out) k.h_out[m] = Vec2{e.x, e.y};
      }
    return out;
  };
  // Two nodes sharing a handle point: a's outgoing is b's incoming.
  auto shares = [](const Node& a, const Node& b) {
    return &a != &b && a.contour == b.contour && !a.out_line && !b.in_line && a.out == b.in;
  };
  // The exact gate's rule of node k at master m (g1_least_move).
  auto rule_of = [&](const Node& k, std::size_t m) {
    G1NodeRule r{k.p[m], k.h_in[m], k.h_out[m], k.in_line, k.out_line, {}, false};
    for (const auto& [a, b] : pieces) {
      if ((a != m && b != m) || !judged(k, a, b)) continue;
      const std::size_t o = a == m ? b : a;
      r.others.push_back({k.p[o] - k.h_in[o], k.h_out[o] - k.p[o]});
    }
    const Vec2 u = k.p[m] - k.h_in[m], v = k.h_out[m] - k.p[m];
    r.keep_g1 = k.smooth[m] && g1_at(Rational(u.x), Rational(u.y), Rational(v.x), Rational(v.y));
    return r;
  };
  for (std::size_t m = 0; m < n; ++m) {
    MastersG1Fix fix;
    fix.master = sources[m]->name;
    fix.ufo = sources[m]->path.string();
    fix.glif = g[m].source;
    fix.kinks_before = kinks(nodes);
    fix.least = T == 0;
    bool ok = true;
    std::vector<std::size_t> done;
    std::vector<bool> constrained;  // the node has a rule at m (judged on a piece with m, or smooth and G1 there)
    for (const Node& x : nodes) {
      const G1NodeRule r = rule_of(x, m);
      constrained.push_back(r.keep_g1 || !r.others.empty());
    }
    for (std::size_t i = 0; i < nodes.size() && ok; ++i) {
      const Node& k = nodes[i];
      bool kinked = false, elsewhere = false;
      for (const auto& [a, b] : pieces)
        if (kink(k, a, b)) (a == m || b == m ? kinked : elsewhere) = true;
      if (!kinked && !elsewhere) continue;
      if (elsewhere || std::find(done.begin(), done.end(), i) != done.end()) {
        if (elsewhere && unfixable.empty()) unfixable = k.name;
        ok = !elsewhere;
        continue;
      }
      if (T == 0) {
        // The run of nodes joined to k by shared handles (each with a rule
        // at m: a node without one leaves its handles free), in contour
        // order, or the closed ring of them; searched together.
        auto linked = [&](std::size_t a, std::size_t b) {
          return shares(nodes[a], nodes[b]) && constrained[a] && constrained[b];
        };
        auto before = [&](std::size_t j) -> std::optional<std::size_t> {
          for (std::size_t x = 0; x < nodes.size(); ++x)
            if (linked(x, j)) return x;
          return std::nullopt;
        };
        auto after = [&](std::size_t j) -> std::optional<std::size_t> {
          for (std::size_t x = 0; x < nodes.size(); ++x)
            if (linked(j, x)) return x;
          return std::nullopt;
        };
        std::size_t first = i, steps = 0;
        auto group_guard = [&] { return ++steps <= nodes.size(); };  // each node has one neighbour each way
        bool ring = false;
        for (std::optional<std::size_t> b = before(i); b && group_guard(); b = before(first)) {
          if (*b == i) {
            ring = true;
            break;
          }
          first = *b;
        }
        std::vector<std::size_t> group{first};
        for (std::optional<std::size_t> a = after(first); a && *a != first && group.size() <= nodes.size(); a = after(*a))
          group.push_back(*a);
        std::vector<G1NodeRule> rules;
        for (const std::size_t j : group) rules.push_back(rule_of(nodes[j], m));
        const std::optional<G1LeastMove> least = g1_least_move(rules, ring);
        if (least)
          for (std::size_t x = 0; x < group.size() && ok; ++x)
            ok = record(fix, nodes[group[x]], m, least->nodes[x].in_handle, least->nodes[x].out_handle);
        if (!least || !ok) {
          if (unfixable.empty()) unfixable = k.name;
          ok = false;
          break;
        }
        fix.distance += least->distance;
        done.insert(done.end(), group.begin(), group.end());
        continue;
      }
      // g1-between-masters:DEG: three families of grid moves against each
      // neighbour of m (g1_between_fix: exactly G1 throughout; m's own
      // tangents in o's length ratio; m's handles on o's tangents), tried
      // cheapest first, each judged exactly on every piece with m.
      std::optional<G1NodeFix> chosen;
      for (const auto& [a, b] : pieces) {
        if ((a != m && b != m) || !judged(k, a, b)) continue;
        const std::size_t o = a == m ? b : a;
        const Vec2 p[2] = {k.p[m], k.p[o]}, in[2] = {k.h_in[m], k.h_in[o]}, out[2] = {k.h_out[m], k.h_out[o]};
        std::vector<G1NodeFix> candidates;
        if (const std::optional<G1NodeFix> f = g1_between_fix(p, in, out, k.in_line, k.out_line)) candidates.push_back(*f);
        for (const G1NodeFix& f : ratio_turn_fixes(p, in, out, k.in_line, k.out_line)) candidates.push_back(f);
        if (!k.in_line && !k.out_line)
          if (const std::optional<G1NodeFix> f = parallel_turn_fix(p, in, out)) candidates.push_back(*f);
        std::stable_sort(candidates.begin(), candidates.end(),
                         [](const G1NodeFix& x, const G1NodeFix& y) { return x.distance < y.distance; });
        for (const G1NodeFix& f : candidates) {
          if (chosen && chosen->distance <= f.distance) break;
          Node trial = k;
          trial.h_in[m] = f.in_handle;
          trial.h_out[m] = f.out_handle;
          bool holds = true;
          for (const auto& [x, y] : pieces)
            if ((x == m || y == m) && kink(trial, x, y)) holds = false;
          if (holds) {
            chosen = f;
            break;
          }
        }
      }
      if (!chosen || !record(fix, k, m, chosen->in_handle, chosen->out_handle)) {
        if (unfixable.empty()) unfixable = k.name;
        ok = false;
        break;
      }
      fix.distance += chosen->distance;
    }
    if (!ok) continue;
    fix.kinks_after = kinks(applied(fix, m));
    if (fix.kinks_after != 0) {  // a move another node's edit undid (g1-between-masters:DEG): not this master
      if (unfixable.empty()) unfixable = glyph + " (the moves, re-judged together, leave kinks)";
      continue;
    }
    if (best.distance < 0 || fix.distance < best.distance) best = fix;
  }
  if (best.distance < 0)
    throw InputError(path + ": " + unfixable +
                     ": no move of its handles on the integer grid in one master (within 1024 units) makes it G1 "
                     "between the masters (off the grid, its tangents reverse, masters on both sides of it need "
                     "other handle ratios and tangents, or a line beside it, whose length stays, leaves no grid "
                     "length for its handle)");
  return best;
}

}  // namespace cmr::report
