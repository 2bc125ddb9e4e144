#include "bezierize/fix.hpp"

#include "bezierize/extremum_terms.hpp"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <random>
#include <set>

#include "bezierize/bernstein.hpp"
#include "bezierize/bounded.hpp"
#include "bezierize/extract.hpp"
#include "bezierize/lambda.hpp"
#include "bezierize/region.hpp"
#include "bezierize/region_setup.hpp"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"

namespace cmr {

// ---------------------------------------------------------------- requirements

FixRequirement parse_fix_requirement(const std::string& text) {
  FixRequirement r;
  if (text == "cmrwi") return r.kind = FixRequirement::Kind::cmrwi, r;
  if (text == "cmr") return r.kind = FixRequirement::Kind::cmr, r;
  // extrema-at-nodes: the gate's name before issue 36, kept as an alias.
  if (text == "curvature-extrema-at-nodes" || text == "extrema-at-nodes")
    return r.kind = FixRequirement::Kind::extrema_at_nodes, r;
  if (text == "each-piece") return r.kind = FixRequirement::Kind::each_piece, r;
  if (text == "no-inflection") return r.kind = FixRequirement::Kind::no_inflection, r;
  if (text == "each-run") return r.kind = FixRequirement::Kind::each_run, r;
  if (text.rfind("g2-at-smooth-nodes", 0) == 0) {
    r.kind = FixRequirement::Kind::g2;
    if (text.size() == 18) return r;
    if (text[18] == ':') {
      const char* b = text.data() + 19;
      const auto [end, ec] = std::from_chars(b, text.data() + text.size(), r.g2_tolerance);
      if (end != b && ec == std::errc() && end == text.data() + text.size() && std::isfinite(r.g2_tolerance) &&
          r.g2_tolerance >= 0)
        return r;
      throw InputError("--require: '" + text + "' needs a relative tolerance >= 0 (g2-at-smooth-nodes:0.05)");
    }
  }
  if (text.rfind("split:", 0) == 0) {
    std::string s = text.substr(6);
    r.kind = FixRequirement::Kind::split;
    const std::size_t colon = s.find(':');
    if (colon != std::string::npos) {
      const std::string e = s.substr(colon + 1);
      if (e == "max" || e == "min")
        throw InputError("--require: '" + text +
                         "' reads signed curvature, which flips with the direction of travel: use split:S:sharpest "
                         "or :flattest");
      if (e == "sharpest")
        r.extremum = FixRequirement::Extremum::sharpest;
      else if (e == "flattest")
        r.extremum = FixRequirement::Extremum::flattest;
      else
        s = "x";  // not a joint: the message below
      if (s != "x") s.resize(colon);
    }
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), r.split);
    if (!s.empty() && ec == std::errc() && end == s.data() + s.size()) return r;
  }
  throw InputError("--require: '" + text +
                   "' is not cmrwi, cmr, split:S, split:S:sharpest|flattest, each-piece, curvature-extrema-at-nodes "
                   "(alias extrema-at-nodes), no-inflection, g2-at-smooth-nodes[:tol] or each-run");
}

std::string to_string(const FixRequirement& r) {
  switch (r.kind) {
    case FixRequirement::Kind::cmrwi: return "cmrwi";
    case FixRequirement::Kind::cmr: return "cmr";
    case FixRequirement::Kind::extrema_at_nodes: return "curvature-extrema-at-nodes";
    case FixRequirement::Kind::each_piece: return "each-piece";
    case FixRequirement::Kind::no_inflection: return "no-inflection";
    case FixRequirement::Kind::each_run: return "each-run";
    case FixRequirement::Kind::g2: {
      char buf[64];
      std::snprintf(buf, sizeof buf, "g2-at-smooth-nodes:%g", r.g2_tolerance);
      return buf;
    }
    case FixRequirement::Kind::split:
      return "split:" + std::to_string(r.split) +
             (r.extremum == FixRequirement::Extremum::sharpest   ? ":sharpest"
              : r.extremum == FixRequirement::Extremum::flattest ? ":flattest"
                                                                 : "");
  }
  return {};
}

const char* to_string(Keep keep) {
  switch (keep) {
    case Keep::none: return "none";
    case Keep::g1: return "g1";
    case Keep::g2: return "g2";
  }
  return "";
}

AnalyzeOptions fix_analyze_options(const FixRequirement& requirement, int max_depth) {
  AnalyzeOptions ao;
  ao.classify.max_depth = max_depth;
  if (requirement.kind == FixRequirement::Kind::split) ao.split = requirement.split;
  ao.each_piece = requirement.kind == FixRequirement::Kind::each_piece;  // each piece (or group) its own
  if (ao.each_piece) ao.splits = requirement.cuts;
  ao.segments = requirement.segments;
  ao.split_mode = Mode::cmrwi;
  return ao;
}

namespace {

double norm(Vec2 v) { return std::sqrt(dot(v, v)); }

bool monotone(Direction d) { return d == Direction::increasing || d == Direction::decreasing; }

bool monotone_class(const SegmentClass& c) {
  const Curvature k = c.monotonicity.curvature;
  return k == Curvature::increasing || k == Curvature::decreasing || k == Curvature::constant;
}

bool split_ok(const SplineAnalysis& a, const FixRequirement& r) {
  if (!a.split || (*a.split != Split::inc_dec && *a.split != Split::dec_inc)) return false;
  if (r.extremum == FixRequirement::Extremum::any) return true;
  for (const Joint& j : a.joints) {
    if (j.index != r.split) continue;
    const std::optional<ExtremumKind> kind = split_extremum_kind(*a.split, j);
    return kind && *kind == (r.extremum == FixRequirement::Extremum::sharpest ? ExtremumKind::sharpest
                                                                              : ExtremumKind::flattest);
  }
  return false;
}

}  // namespace

FixRequirement resolve_requirement(const BSpline& spline, FixRequirement r) {
  if (r.kind != FixRequirement::Kind::each_run) return r;
  r.cuts.clear();
  const std::vector<double>& t = spline.knots();
  const int d = spline.degree();
  for (const Segment& seg : spline.segments()) {
    if (seg.index == 0) continue;  // the seam or the start: no joint inside the range
    if (r.segments && (seg.index <= r.segments->first || seg.index > r.segments->last)) continue;
    int mult = 0;
    for (double u : t) mult += u == seg.a;
    if (mult >= d) r.cuts.push_back(seg.index);
  }
  r.kind = r.cuts.empty() ? FixRequirement::Kind::cmrwi : FixRequirement::Kind::each_piece;
  return r;
}

namespace {

/// The curvature on both sides of a joint, as the analysis certifies them, agrees within tol.
bool g2_ok(const Joint& j, double tol) {
  if (!j.g1 || j.zero_tangent || j.pole || !std::isfinite(j.kappa_left) || !std::isfinite(j.kappa_right)) return true;
  return std::abs(j.kappa_left - j.kappa_right) <= tol * std::max(std::abs(j.kappa_left), std::abs(j.kappa_right));
}

}  // namespace

bool requirement_holds(const SplineAnalysis& a, const FixRequirement& r) {
  switch (r.kind) {
    case FixRequirement::Kind::each_run:
    case FixRequirement::Kind::each_piece: return a.each_piece && *a.each_piece == EachPiece::monotone;
    case FixRequirement::Kind::no_inflection: {
      int sign = 0;
      for (int i = a.range.first; i <= a.range.last; ++i) {
        const SegmentShape& sh = a.shapes[i];
        if (sh.pole || sh.cusp || sh.inflection != Inflection::none) return false;
        if (sh.straight || sh.kappa_sign == 0) continue;
        if (sign != 0 && sh.kappa_sign != sign) return false;
        sign = sh.kappa_sign;
      }
      for (const Joint& j : a.joints)
        if (j.zero_tangent && a.judged(j.index - 1) && a.judged(j.index)) return false;
      return !(a.seam && a.seam->zero_tangent);
    }
    case FixRequirement::Kind::g2:
      for (const Joint& j : a.joints)
        if (a.judged(j.index - 1) && a.judged(j.index) && !g2_ok(j, r.g2_tolerance)) return false;
      return !a.seam || g2_ok(*a.seam, r.g2_tolerance);
    case FixRequirement::Kind::cmrwi: return monotone(a.cmrwi);
    case FixRequirement::Kind::cmr: return monotone(a.cmr);
    case FixRequirement::Kind::split: return split_ok(a, r);
    case FixRequirement::Kind::extrema_at_nodes:
      for (int i = a.range.first; i <= a.range.last; ++i)
        if (a.shapes[i].pole || !monotone_class(a.segments[i])) return false;
      return true;
  }
  return false;
}

bool requirement_holds(const BSpline& spline, const FixRequirement& requirement, int max_depth) {
  const FixRequirement r = resolve_requirement(spline, requirement);
  return requirement_holds(analyze(spline, fix_analyze_options(r, max_depth)), r);
}

// ------------------------------------------------------------ segment helpers

std::vector<int> segment_points(const BSpline& spline, const Segment& s) {
  const int d = spline.degree(), m = spline.unique_point_count();
  std::vector<int> out;
  for (int k = s.span - d + 1; k <= s.span + 1; ++k) {
    const int u = spline.closed() ? k % m : k;
    if (std::find(out.begin(), out.end(), u) == out.end()) out.push_back(u);
  }
  return out;
}

namespace {

/// A segment that fails the requirement on its own: not certified monotone
/// (or a pole), or for cmr an exact inflection.
bool segment_alone_bad(const SplineAnalysis& a, int i, const FixRequirement& r) {
  if (a.shapes[i].pole || !monotone_class(a.segments[i])) return true;
  return r.kind == FixRequirement::Kind::cmr && a.shapes[i].inflection != Inflection::none;
}

}  // namespace


double curve_size(const BSpline& s) {
  Vec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (int k = 0; k < s.unique_point_count(); ++k) lo = Vec2(std::min(lo.x, s.points()[k].x), std::min(lo.y, s.points()[k].y)), hi = Vec2(std::max(hi.x, s.points()[k].x), std::max(hi.y, s.points()[k].y));
  const double d = norm(hi - lo);
  return d > 0 ? d : 1.0;
}

namespace {

// ------------------------------------------------------------------- units

/// A unit of motion: every point translates by the same 2-D vector, or (slide)
/// the one point moves along `dir`.
struct Unit {
  std::vector<int> points;  // leader first
  bool slide = false;
  Vec2 dir{0.0};
  int dims() const { return slide ? 1 : 2; }
};

/// The node of joint i (its knot has multiplicity d): the point whose polar
/// label is that knot repeated (unique index), or -1.
int node_of(const BSpline& s, double knot) {
  const int d = s.degree(), m = s.unique_point_count();
  const std::vector<double>& t = s.knots();
  for (int k = 0; k + d - 1 < static_cast<int>(t.size()); ++k)
    if (t[k] == knot && t[k + d - 1] == knot) return s.closed() ? k % m : k;
  return -1;
}

/// Unique points whose moving changes a derivative of order <= order at the
/// end of segment `left` or the start of segment `right` (the Bezier points
/// that carry that jet depend on them; found by moving each point).
std::vector<int> jet_points(const BSpline& s, int left, int right, int order) {
  const Segment& L = s.segments()[left];
  const Segment& R = s.segments()[right];
  const BezierSegment bl = bezier_segment(s, L), br = bezier_segment(s, R);
  const int d = s.degree();
  std::vector<int> out;
  std::set<int> candidates;
  for (int k : segment_points(s, L)) candidates.insert(k);
  for (int k : segment_points(s, R)) candidates.insert(k);
  for (const int k : candidates) {
    const BSpline moved = s.with_point(k, s.points()[k] + Vec2(1.0, 1.0));
    const BezierSegment ml = bezier_segment(moved, L), mr = bezier_segment(moved, R);
    bool depends = false;
    for (int j = 0; j <= std::min(order, d); ++j)
      depends = depends || ml.points[d - j] != bl.points[d - j] || mr.points[j] != br.points[j];
    if (depends) out.push_back(k);
  }
  return out;
}

/// Union-find over point indices (groups that translate together).
struct Groups {
  std::vector<int> parent;
  explicit Groups(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) { return parent[a] == a ? a : parent[a] = find(parent[a]); }
  void join(int a, int b) { parent[find(a)] = find(b); }
};

struct Ties {
  std::vector<int> joints;            // joint indices (N: a closed spline's seam) kept
  std::vector<Unit> units;
  std::vector<bool> moves;            // per unique point: some unit moves it
  /// Each handle of a G1 tie: (handle, node, unit direction from the node to
  /// the handle). A handle that reaches or passes its node would turn the
  /// tangent round: G1 broken (Search::flips).
  struct Handle {
    int handle, node;
    Vec2 dir;
  };
  std::vector<Handle> handles;
};

/// The joints of an analysis, the seam last.
std::vector<Joint> all_joints(const SplineAnalysis& a) {
  std::vector<Joint> js = a.joints;
  if (a.seam) js.push_back(*a.seam);
  return js;
}

Ties build_units(const BSpline& s, const SplineAnalysis& a, const std::vector<int>& allowed, Keep keep,
                 const std::set<int>& acting) {
  const int m = s.unique_point_count(), N = s.segment_count();
  std::vector<bool> is_allowed(m, false);
  for (int k : allowed) is_allowed[k] = true;
  Groups groups(m);
  std::vector<bool> grouped(m, false), frozen(m, false);
  std::vector<std::vector<Vec2>> slides(m);  // tangent directions a handle must keep
  std::vector<bool> node_at_tie(m, false);
  Ties t;
  for (const Joint& j : all_joints(a)) {
    const int left = (j.index - 1 + N) % N, right = j.index % N;
    if (keep == Keep::none || j.pole || j.zero_tangent) continue;
    const bool g1_tie = j.g1 && j.continuity < 1;
    const bool g2_tie = keep == Keep::g2 && j.g2 && j.continuity < 2;
    if (!g1_tie && !g2_tie) continue;
    t.joints.push_back(j.index);
    const int n = node_of(s, j.knot);
    if (g2_tie) {
      const std::vector<int> jet = jet_points(s, left, right, 2);
      const bool leader = n >= 0 ? is_allowed[n] : std::all_of(jet.begin(), jet.end(), [&](int k) { return is_allowed[k]; });
      for (int k : jet) {
        if (leader) {
          grouped[k] = true;
          groups.join(k, jet.front());
        } else {
          frozen[k] = true;
        }
      }
      continue;
    }
    if (n < 0) continue;  // G1 at a C0 joint always has a node; be safe
    const int hm = (n - 1 + m) % m, hp = (n + 1) % m;
    if (!s.closed() && (n == 0 || n == m - 1)) continue;
    node_at_tie[n] = true;
    if (is_allowed[n]) {
      for (int k : {hm, n, hp}) grouped[k] = true, groups.join(k, n);
    }
    for (int h : {hm, hp}) {
      const Vec2 dir = s.points()[h] - s.points()[n];
      const double len = norm(dir);
      if (len > 0) slides[h].push_back(dir / len), t.handles.push_back({h, n, dir / len}); else frozen[h] = true;
    }
  }
  // Translation groups (led by their smallest allowed point).
  std::vector<std::vector<int>> members(m);
  for (int k = 0; k < m; ++k)
    if (grouped[k]) members[groups.find(k)].push_back(k);
  for (int r = 0; r < m; ++r) {
    if (members[r].empty()) continue;
    std::vector<int> pts = members[r];
    bool any_acting = false;
    for (int k : pts) any_acting = any_acting || acting.count(k);
    if (!any_acting) continue;
    // Leader: an allowed member (the node when there is one).
    auto lead = std::find_if(pts.begin(), pts.end(), [&](int k) { return is_allowed[k] && node_at_tie[k]; });
    if (lead == pts.end()) lead = std::find_if(pts.begin(), pts.end(), [&](int k) { return is_allowed[k]; });
    if (lead == pts.end()) continue;
    std::iter_swap(pts.begin(), lead);
    t.units.push_back(Unit{pts, false, Vec2(0.0)});
  }
  // Single points: free, sliding, or held.
  for (int k : allowed) {
    if (!acting.count(k) || frozen[k] || node_at_tie[k]) continue;
    if (keep == Keep::g2 && grouped[k]) continue;  // G2 jets move only with their group
    if (slides[k].empty()) {
      if (!grouped[k]) t.units.push_back(Unit{{k}, false, Vec2(0.0)});
    } else if (slides[k].size() == 1) {
      t.units.push_back(Unit{{k}, true, slides[k][0]});
    }  // between two ties: held
  }
  t.moves.assign(m, false);
  for (const Unit& u : t.units)
    for (int k : u.points) t.moves[k] = true;
  return t;
}

// ---------------------------------------------------------------- local checks

/// The kinds judged one check at a time (extrema-at-nodes, no-inflection,
/// g2): check i is judged segment i (g2: the joint that starts segment i),
/// decided on a moved spline from the points that act on it alone, so a move
/// re-judges only the checks it touches.
bool local_kind(FixRequirement::Kind k) {
  return k == FixRequirement::Kind::extrema_at_nodes || k == FixRequirement::Kind::no_inflection ||
         k == FixRequirement::Kind::g2;
}

/// The points that act on check i (unique indices).
std::vector<int> check_points(const BSpline& s, FixRequirement::Kind kind, int i) {
  std::vector<int> pts = segment_points(s, s.segments()[i]);
  const int N = s.segment_count();
  if (kind == FixRequirement::Kind::g2 && (s.closed() || i > 0))
    for (int k : segment_points(s, s.segments()[(i - 1 + N) % N]))
      if (std::find(pts.begin(), pts.end(), k) == pts.end()) pts.push_back(k);
  return pts;
}

/// Signed curvature at the start (side 0) or end (side 1) of a polynomial
/// segment from its Bezier points, in doubles: (d-1)/d cross(b, a) / |a|^3
/// with a, b the end's first and second control-polygon legs. NaN for a
/// rational segment or a zero end leg.
double end_curvature(const BSpline& s, const Segment& seg, int side) {
  if (s.is_rational() || s.degree() < 2) return std::numeric_limits<double>::quiet_NaN();
  const int d = s.degree();
  // The three Bezier points at that end, B_k = f(a^{d-k}, b^k), each the
  // blossom bezier_segment computes (the same doubles), the others unneeded.
  std::vector<Vec2> p(static_cast<std::size_t>(d + 1));
  std::vector<double> args(static_cast<std::size_t>(d));
  for (int k = side == 0 ? 0 : d - 2; k <= (side == 0 ? 2 : d); ++k) {
    for (int i = 0; i < d; ++i) args[i] = i < d - k ? seg.a : seg.b;
    p[k] = blossom_span(s.knots(), s.points(), d, seg.span, args.data());
  }
  const Vec2 a = side == 0 ? p[1] - p[0] : p[d] - p[d - 1];
  const Vec2 b = side == 0 ? p[2] - p[1] : p[d - 1] - p[d - 2];
  const double la = norm(a);
  if (!(la > 0)) return std::numeric_limits<double>::quiet_NaN();
  const double c = side == 0 ? det(a, b) : det(b, a);
  return (d - 1.0) / d * c / (la * la * la);
}

/// Whether check i fails on a spline (exact or certified, as the final
/// analysis decides it).
struct LocalJudge {
  FixRequirement requirement;
  int max_depth = kDefaultDepth;
  int sign = 0;                    ///< no-inflection: the curvature sign every segment must keep (the input's majority)
  std::vector<char> judged_joint;  ///< g2: the joint starting segment i is judged (smooth in the input)

  bool bad(const BSpline& s, int i) const {
    const Segment& seg = s.segments()[i];
    switch (requirement.kind) {
      case FixRequirement::Kind::no_inflection: {
        if (!s.is_rational()) {
          // Most positions: eta's Bernstein coefficients certainly of one
          // sign (error-bounded doubles) mean no inflection and no cusp
          // (eta != 0 needs P' != 0), kappa of that sign throughout.
          Bernstein<Bounded> eta = eta_bernstein<Bounded>(segment_bezier_points<Bounded>(s, seg));
          const int e = strict_sign(eta);
          if (e != 0) return sign != 0 && e != sign;
          // Certainly bad: eta certainly against the sign at an end or at
          // the middle (de Casteljau in error-bounded doubles), or certainly
          // of opposite signs at the two ends.
          if (!eta.empty()) {
            const int e0 = certain_sign(eta.front()), e1 = certain_sign(eta.back());
            if (e0 * e1 < 0 || (sign != 0 && (e0 == -sign || e1 == -sign))) return true;
            for (std::size_t r = eta.size(); r-- > 1;)
              for (std::size_t k = 0; k < r; ++k) eta[k] = (eta[k] + eta[k + 1]).half();
            if (sign != 0 && certain_sign(eta.front()) == -sign) return true;
          }
        }
        const SegmentShape sh = segment_shape(s, seg);
        if (sh.pole || sh.cusp || sh.inflection != Inflection::none) return true;
        return !sh.straight && sh.kappa_sign != 0 && sign != 0 && sh.kappa_sign != sign;
      }
      case FixRequirement::Kind::g2: {
        if (!judged_joint[i]) return false;
        const int N = s.segment_count();
        const Segment& left = s.segments()[(i - 1 + N) % N];
        // The end curvatures from the Bezier points in doubles, judged with a
        // margin of 2% of the tolerance (the certificate's analyze decides
        // with the certified curvatures, kKappaRelError); a rational or
        // degenerate end: the certified values.
        double kl = end_curvature(s, left, 1), kr = end_curvature(s, seg, 0), tol = 0.98 * requirement.g2_tolerance;
        if (!std::isfinite(kl) || !std::isfinite(kr)) {
          kl = certified_end_curvature(s, left, 1), kr = certified_end_curvature(s, seg, 0);
          tol = requirement.g2_tolerance;
        }
        if (!std::isfinite(kl) || !std::isfinite(kr)) return true;
        return std::abs(kl - kr) > tol * std::max(std::abs(kl), std::abs(kr));
      }
      default:
        return !segment_poles(s, seg).empty() || !monotone_class(classify_segment(s, seg, {max_depth, false}));
    }
  }
};

/// The judge of a local kind for the input spline and its analysis.
LocalJudge make_judge(const BSpline& s, const SplineAnalysis& a, const FixRequirement& r, int max_depth) {
  LocalJudge j{r, max_depth, 0, {}};
  const int N = s.segment_count();
  if (r.kind == FixRequirement::Kind::no_inflection) {
    int plus = 0, minus = 0;
    for (int i = a.range.first; i <= a.range.last; ++i)
      if (!a.shapes[i].straight) plus += a.shapes[i].kappa_sign > 0, minus += a.shapes[i].kappa_sign < 0;
    j.sign = plus >= minus ? 1 : -1;
  }
  if (r.kind == FixRequirement::Kind::g2) {
    j.judged_joint.assign(N, 0);
    for (const Joint& jt : all_joints(a)) {
      const int i = jt.index % N, left = (i - 1 + N) % N;
      if (!a.judged(i) || !a.judged(left)) continue;
      j.judged_joint[i] = jt.g1 && !jt.zero_tangent && !jt.pole && std::isfinite(jt.kappa_left) &&
                          std::isfinite(jt.kappa_right);
    }
  }
  return j;
}

}  // namespace

std::vector<int> failing_segments(const BSpline& spline, const SplineAnalysis& a, const FixRequirement& r) {
  std::vector<int> out;
  if (r.kind == FixRequirement::Kind::no_inflection || r.kind == FixRequirement::Kind::g2) {
    // The checks that fail; g2's joint i fails both its segments.
    const LocalJudge judge = make_judge(spline, a, r, kDefaultDepth);
    const int N = spline.segment_count();
    std::set<int> segs;
    for (int i = a.range.first; i <= a.range.last; ++i)
      if (judge.bad(spline, i)) {
        segs.insert(i);
        if (r.kind == FixRequirement::Kind::g2) segs.insert((i - 1 + N) % N);
      }
    return {segs.begin(), segs.end()};
  }
  for (int i = a.range.first; i <= a.range.last; ++i)
    if (segment_alone_bad(a, i, r)) out.push_back(i);
  if (out.empty() && !requirement_holds(a, r))
    for (int i = a.range.first; i <= a.range.last; ++i) out.push_back(i);
  return out;
}

namespace {

// ---------------------------------------------------------------- the search

using Clock = std::chrono::steady_clock;

/// A state of the search: one displacement per unique point.
struct Search {
  const BSpline& base;
  const FixRequest& request;
  const SplineAnalysis& base_analysis;
  double size = 1, tol = 0, max_move = 0;
  std::atomic<long> evaluations{0};

  LocalJudge judge;
  std::vector<char> base_bad;  ///< local kinds: check i fails on the input
  std::vector<Ties::Handle> handles;  ///< of the G1 ties (set by fix())

  /// Some tied handle reaches or passes its node (a slide of the handle, or
  /// of the node's group against it): the tangent would turn round.
  bool flips(const std::vector<Vec2>& delta) const {
    for (const Ties::Handle& h : handles) {
      const Vec2 off = base.points()[h.handle] + delta[h.handle] - base.points()[h.node] - delta[h.node];
      if (!(dot(off, h.dir) > 0)) return true;
    }
    return false;
  }

  Search(const BSpline& b, const FixRequest& r, const SplineAnalysis& a)
      : base(b), request(r), base_analysis(a), judge(make_judge(b, a, r.requirement, r.max_depth)) {
    if (!local_kind(r.requirement.kind)) return;
    base_bad.assign(b.segment_count(), 0);
    for (int i = a.range.first; i <= a.range.last; ++i) base_bad[i] = judge.bad(b, i);
  }

  BSpline moved(const std::vector<Vec2>& delta) const {
    // One copy of the spline per moved point (with_point), none more.
    std::optional<BSpline> s;
    for (std::size_t k = 0; k < delta.size(); ++k)
      if (delta[k] != Vec2(0.0)) s = (s ? *s : base).with_point(static_cast<int>(k), base.points()[k] + delta[k]);
    return s ? std::move(*s) : base;
  }

  /// The requirement on a moved spline: extrema-at-nodes re-classifies only
  /// the segments a moved point acts on; the others analyze the whole spline.
  bool holds(const std::vector<Vec2>& delta) {
    ++evaluations;
    if (expired()) return false;
    for (const Vec2& d : delta)
      if (norm(d) > max_move) return false;
    if (flips(delta)) return false;
    if (request.judge) return request.judge(moved(delta)) == 0;
    if (local_kind(request.requirement.kind)) return bad_segments(delta, true) == 0;
    return requirement_holds(moved(delta), request.requirement, request.max_depth);
  }

  /// extrema-at-nodes: how many judged segments are not certified monotone
  /// after the move (only the segments a moved point acts on are classified
  /// again); with `first`, stops at the first.
  int bad_segments(const std::vector<Vec2>& delta, bool first) {
    const BSpline s = moved(delta);
    int bad = 0;
    for (int i = base_analysis.range.first; i <= base_analysis.range.last && !(first && bad); ++i) {
      bool touched = false;
      for (int k : check_points(s, request.requirement.kind, i)) touched = touched || delta[k] != Vec2(0.0);
      bad += touched ? judge.bad(s, i) : base_bad[i];
    }
    return bad;
  }

  /// extrema-at-nodes: how many of the judged segments `segments` are not
  /// certified monotone after the move (each classified again).
  int bad_in(const std::vector<Vec2>& delta, const std::vector<int>& segments) {
    if (flips(delta)) return std::numeric_limits<int>::max() / 2;
    const BSpline s = moved(delta);
    int bad = 0;
    for (int i : segments) bad += judge.bad(s, i);
    return bad;
  }

  /// The search's time is up (FixRequest::max_seconds, or the caller's
  /// cancel flag): every predicate answers "fails" from now on, so every
  /// loop ends.
  bool expired() {
    if (!timed_out && request.max_seconds > 0 && Clock::now() > deadline) timed_out = true;
    if (!timed_out && request.cancel != nullptr && request.cancel->load(std::memory_order_relaxed)) timed_out = true;
    return timed_out;
  }
  Clock::time_point deadline;
  std::atomic<bool> timed_out{false};

  /// How far a moved spline is from the requirement (0: it holds): 4 per
  /// segment that fails alone, 1 per segment against the majority direction
  /// (of its part, with a split) and per joint whose jump goes against the
  /// verdict; at least 1 while the requirement fails. Each greedy step must
  /// lower it.
  int badness(const std::vector<Vec2>& delta) {
    ++evaluations;
    if (expired()) return std::numeric_limits<int>::max();
    for (const Vec2& d : delta)
      if (norm(d) > max_move) return std::numeric_limits<int>::max();
    if (flips(delta)) return std::numeric_limits<int>::max();
    if (request.judge) return request.judge(moved(delta));
    if (local_kind(request.requirement.kind)) return bad_segments(delta, false);
    const SplineAnalysis a = analyze(moved(delta), fix_analyze_options(request.requirement, request.max_depth));
    if (requirement_holds(a, request.requirement)) return 0;
    int score = 0;
    for (int i = a.range.first; i <= a.range.last; ++i) score += 4 * segment_alone_bad(a, i, request.requirement);
    if (request.requirement.kind != FixRequirement::Kind::extrema_at_nodes) {
      const bool split = request.requirement.kind == FixRequirement::Kind::split;
      std::vector<std::pair<int, int>> parts;
      if (split)
        parts = {{a.range.first, request.requirement.split}, {request.requirement.split, a.range.last + 1}};
      else
        parts = {{a.range.first, a.range.last + 1}};
      for (const auto& [first, end] : parts) {
        int inc = 0, dec = 0;
        for (int i = first; i < end; ++i) {
          inc += a.segments[i].monotonicity.curvature == Curvature::increasing;
          dec += a.segments[i].monotonicity.curvature == Curvature::decreasing;
        }
        score += std::min(inc, dec);
      }
      score += static_cast<int>(a.joint_conflicts.size());
    }
    return std::max(score, 1);
  }
};

/// The passing position nearest to 0 of pass(x), x = t * dir (dims 1) or x in
/// the plane (dims 2): see the header comment, step 1.
struct Nearest {
  bool found = false;
  Vec2 x{0.0};
  double dist = std::numeric_limits<double>::infinity();
};

Nearest nearest(const std::function<bool(Vec2)>& pass, int dims, Vec2 dir, double size, double max_move, double tol,
                int grid, int threads, std::size_t max_seeds = 6, bool refine = false,
                const std::function<bool(Vec2)>& certify = {}) {
  // Cell (i, j) of an n x n grid of half-width w centred on c (in the unit's
  // coordinates: dims 1 uses c.x as the parameter t along dir).
  auto at = [&](Vec2 c, double w, int n, int i, int j) {
    const double u = c.x + w * (2.0 * (i + 0.5) / n - 1.0);
    const double v = c.y + w * (2.0 * (j + 0.5) / n - 1.0);
    return dims == 1 ? Vec2(u * dir.x, u * dir.y) : Vec2(u, v);
  };
  // The passing cell centres of a grid, nearest to 0 first.
  auto scan = [&](Vec2 c, double w, int n) {
    const int rows = dims == 1 ? 1 : n;
    std::vector<char> ok(static_cast<std::size_t>(n) * rows, 0);
    parallel_for(ok.size(), threads, [&](std::size_t idx) {
      const Vec2 x = at(c, w, n, static_cast<int>(idx % n), static_cast<int>(idx / n));
      if (norm(x) <= max_move) ok[idx] = pass(x);
    });
    std::vector<Nearest> found;
    for (std::size_t idx = 0; idx < ok.size(); ++idx)
      if (ok[idx]) {
        const Vec2 x = at(c, w, n, static_cast<int>(idx % n), static_cast<int>(idx / n));
        found.push_back(Nearest{true, x, norm(x)});
      }
    std::sort(found.begin(), found.end(), [](const Nearest& p, const Nearest& q) { return p.dist < q.dist; });
    return found;
  };
  // 1. Grow a grid around the point until something passes.
  double w = std::min(size / 16, max_move);
  const int n1 = dims == 1 ? grid * 4 : grid;
  std::vector<Nearest> cells;
  for (;;) {
    cells = scan(Vec2(0.0), w, n1);
    if (!cells.empty()) break;
    if (w >= max_move) return Nearest{};
    w = std::min(2 * w, max_move);
  }
  // 2. A finer grid over the disc of the distance found.
  if (cells.front().dist < w * 0.9) {
    const double w2 = cells.front().dist * (1 + 2.0 / n1);
    std::vector<Nearest> finer = scan(Vec2(0.0), w2, n1);
    if (!finer.empty() && finer.front().dist <= cells.front().dist) cells = std::move(finer), w = w2;
  }
  double cell = 2 * w / n1;
  // 2b. Below the first cell (dims 2, when refine): a passing region thinner
  // than a cell (a sliver along a boundary, a wedge tip) may come nearer the
  // point than any passing cell centre shows. Each level halves the cell:
  // the children of every passing cell and of its 8 neighbours are
  // classified, then the neighbours of every new passing child (a flood that
  // follows a sliver along its length at that level), each only while its
  // lower distance bound (centre distance less half a diagonal) is below the
  // best passing distance D; down to a cell of D / 512 (or the tolerance).
  const std::vector<Nearest> first_cells(cells.begin(), cells.begin() + std::min<std::size_t>(cells.size(), max_seeds));
  if (dims == 2 && refine) {
    using Key = std::pair<long long, long long>;
    const double o = -w;  // the lattice of every level: centres o + (i + 1/2) h
    Nearest best_cell = cells.front();
    std::vector<Key> prev;
    for (const Nearest& c : cells)
      if (c.dist - 1.5 * std::sqrt(2.0) * cell < best_cell.dist)
        prev.emplace_back(std::llround((c.x.x - o) / cell - 0.5), std::llround((c.x.y - o) / cell - 0.5));
    double h = cell;
    long budget = 16L * n1 * n1;  // classifier calls below the first cell: 16 first grids
    while (!prev.empty() && h > best_cell.dist / 512 && h > tol && budget > 0) {
      const double hc = h / 2, half_diag = hc / std::sqrt(2.0);
      auto centre = [&](Key k) { return Vec2(o + (k.first + 0.5) * hc, o + (k.second + 0.5) * hc); };
      std::set<Key> seen;
      std::vector<Key> batch;
      auto want = [&](Key k) {
        if (seen.insert(k).second && norm(centre(k)) - half_diag < best_cell.dist) batch.push_back(k);
      };
      for (const Key& p : prev)
        for (long long di = -1; di <= 1; ++di)
          for (long long dj = -1; dj <= 1; ++dj)
            for (long long a = 0; a < 2; ++a)
              for (long long b = 0; b < 2; ++b) want({2 * (p.first + di) + a, 2 * (p.second + dj) + b});
      std::vector<Nearest> level;
      std::vector<Key> level_keys;
      const std::vector<Key> first = batch;  // the children of the cells before and of their neighbours
      while (!batch.empty() && budget > 0) {
        std::vector<char> ok(batch.size(), 0);
        budget -= static_cast<long>(batch.size());
        parallel_for(batch.size(), threads, [&](std::size_t t) {
          const Vec2 x = centre(batch[t]);
          if (norm(x) <= max_move) ok[t] = pass(x);
        });
        const std::vector<Key> done = std::move(batch);
        batch.clear();
        for (std::size_t t = 0; t < done.size(); ++t) {
          if (!ok[t]) continue;
          const Vec2 x = centre(done[t]);
          level.push_back(Nearest{true, x, norm(x)});
          level_keys.push_back(done[t]);
          if (level.back().dist < best_cell.dist) best_cell = level.back();
        }
        for (std::size_t t = 0; t < done.size(); ++t)
          if (ok[t])
            for (long long di = -2; di <= 2; ++di)
              for (long long dj = -2; dj <= 2; ++dj) want({done[t].first + di, done[t].second + dj});
      }
      h = hc;
      if (level.empty()) {
        // No centre of this level passes: the region (if the cells before
        // touch one) is thinner still. Descend from this level's cells around
        // the passing ones before; the coarser cells stand meanwhile.
        prev.clear();
        for (const Key& k : first)
          if (norm(centre(k)) - 1.5 * std::sqrt(2.0) * h < best_cell.dist) prev.push_back(k);
        continue;
      }
      prev.clear();
      for (std::size_t t = 0; t < level.size(); ++t)
        if (level[t].dist - 1.5 * std::sqrt(2.0) * h < best_cell.dist) prev.push_back(level_keys[t]);
      level.push_back(best_cell);  // a passing centre of a coarser level may still be the nearest
      std::sort(level.begin(), level.end(), [](const Nearest& p, const Nearest& q) { return p.dist < q.dist; });
      cells = std::move(level);
      cell = h;
    }
  }
  // Seeds: the passing cells that may hold the nearest point (within two cell
  // diagonals of the best), at least three cells apart, at most six.
  std::vector<Nearest> seeds;
  for (const Nearest& c : cells) {
    if (c.dist > cells.front().dist + 2 * std::sqrt(2.0) * cell || seeds.size() >= max_seeds) break;
    bool apart = true;
    for (const Nearest& sd : seeds) apart = apart && norm(sd.x - c.x) >= 3 * cell;
    if (apart) seeds.push_back(c);
  }
  // The nearest passing point on the ray at angle theta, bracketed below
  // r_hi (infinity when r_hi itself fails): bisection to the tolerance.
  auto ray = [&](Vec2 u, double r_hi) {
    if (r_hi > max_move || !pass(r_hi * u)) return std::numeric_limits<double>::infinity();
    double lo = std::max(0.0, r_hi - 8 * cell), hi = r_hi;
    if (lo > 0 && pass(lo * u)) lo = 0;  // 0 always fails (the point does)
    while (hi - lo > tol / 8 && hi - lo > 1e-16 * hi) {
      const double mid = 0.5 * (lo + hi);
      if (pass(mid * u)) hi = mid; else lo = mid;
    }
    return hi;
  };
  Nearest best;
  std::vector<Nearest> candidates;  // with certify: every answer a seed gives, and the seeds
  for (const Nearest& seed : seeds) {
    Nearest local = seed;
    if (dims == 1) {
      // 3. The boundary between the seed and the cell before it (which fails).
      const double t = dot(seed.x, dir), s = t > 0 ? 1.0 : -1.0;
      const double r = ray(s * dir, std::abs(t));
      if (r < local.dist) local = Nearest{true, r * s * dir, r};
    } else {
      // 3. Golden-section search over the angle of the ray, each ray's
      // distance found by bisection: the boundary point nearest the point.
      const double theta0 = std::atan2(seed.x.y, seed.x.x);
      const double span = std::min(3.14159265358979, 3 * cell / std::max(seed.dist, 1e-300));
      const double r_hi = seed.dist + 2 * cell;
      auto f = [&](double th) { return ray(Vec2(std::cos(th), std::sin(th)), r_hi); };
      const double g = (std::sqrt(5.0) - 1) / 2;
      double a = theta0 - span, b = theta0 + span;
      double c = b - g * (b - a), d = a + g * (b - a), fc = f(c), fd = f(d);
      while ((b - a) * r_hi > tol / 4) {
        if (fc <= fd) b = d, d = c, fd = fc, c = b - g * (b - a), fc = f(c);
        else a = c, c = d, fc = fd, d = a + g * (b - a), fd = f(d);
      }
      for (const auto& [th, r] : {std::pair{c, fc}, std::pair{d, fd}, std::pair{theta0, f(theta0)}})
        if (r < local.dist) local = Nearest{true, r * Vec2(std::cos(th), std::sin(th)), r};
    }
    if (local.dist < best.dist) best = local;
    candidates.push_back(local), candidates.push_back(seed);
  }
  // 4. With certify (the requirement's own judge, when the labels are a
  // stricter or looser test than it): the nearest candidate it accepts,
  // the first grid's passing cells last.
  if (!certify || !best.found || certify(best.x)) return best;
  candidates.insert(candidates.end(), first_cells.begin(), first_cells.end());
  std::stable_sort(candidates.begin(), candidates.end(), [](const Nearest& p, const Nearest& q) { return p.dist < q.dist; });
  for (const Nearest& c : candidates)
    if (certify(c.x)) return c;
  return best;
}

/// The passing position nearest to 0 of pass(c) for c in R^dims (dims 3 or 4:
/// several units moved at once): rays from 0 in fixed directions (the axes,
/// the diagonals and seeded random ones), each scanned outwards by factors
/// of 1.5 from size/512 to max_move; the first passing radius of each ray is
/// bisected to `tol` against the radius before it. Coarse: the compass search
/// that follows polishes the total squared displacement.
struct NearestN {
  bool found = false;
  std::vector<double> c;
  double dist = std::numeric_limits<double>::infinity();
};

NearestN nearest_rays(const std::function<bool(const std::vector<double>&)>& pass, int dims, double size,
                      double max_move, double tol, int threads) {
  std::vector<std::vector<double>> dirs;
  for (int i = 0; i < dims; ++i)
    for (const double sg : {-1.0, 1.0}) {
      std::vector<double> d(dims, 0.0);
      d[i] = sg;
      dirs.push_back(d);
    }
  for (int mask = 0; mask < (1 << dims); ++mask) {
    std::vector<double> d(dims);
    for (int i = 0; i < dims; ++i) d[i] = (mask >> i & 1 ? 1.0 : -1.0) / std::sqrt(static_cast<double>(dims));
    dirs.push_back(d);
  }
  std::mt19937 rng(22);
  std::normal_distribution<double> G(0.0, 1.0);
  while (dirs.size() < 96) {
    std::vector<double> d(dims);
    double n2 = 0;
    for (double& v : d) v = G(rng), n2 += v * v;
    for (double& v : d) v /= std::sqrt(n2);
    dirs.push_back(d);
  }
  auto at = [&](const std::vector<double>& d, double r) {
    std::vector<double> c(d);
    for (double& v : c) v *= r;
    return c;
  };
  std::vector<double> radius(dirs.size(), std::numeric_limits<double>::infinity());
  parallel_for(dirs.size(), threads, [&](std::size_t i) {
    double prev = 0;
    for (double r = std::min(size / 512, max_move);; r = std::min(1.5 * r, max_move)) {
      if (pass(at(dirs[i], r))) {
        double lo = prev, hi = r;
        while (hi - lo > tol) {
          const double mid = 0.5 * (lo + hi);
          if (pass(at(dirs[i], mid))) hi = mid; else lo = mid;
        }
        radius[i] = hi;
        return;
      }
      if (r >= max_move) return;
      prev = r;
    }
  });
  NearestN best;
  for (std::size_t i = 0; i < dirs.size(); ++i)
    if (radius[i] < best.dist) best = NearestN{true, at(dirs[i], radius[i]), radius[i]};
  return best;
}

/// The labels of a region request that may pass the requirement. A split
/// pixel with an extremum at the joint is a candidate for :sharpest and
/// :flattest alike: which one it is depends on the sign of kappa at the joint
/// for that position, which the certificate (requirement_holds on analyze)
/// decides for the position found.
bool passing_pixel(const RegionPixel& p, const FixRequirement& r) {
  if (r.kind == FixRequirement::Kind::split)
    return p.split_label == Split::inc_dec || p.split_label == Split::dec_inc;
  if (r.kind == FixRequirement::Kind::each_piece) return p.piece_label == EachPiece::monotone;
  return p.label == Direction::increasing || p.label == Direction::decreasing;
}

/// A prepared region problem (what RegionProblem wraps), classified the way
/// RegionProblem::classify does: prepare_many shares one analysis of the
/// spline (backend::region_base) between several requests, which
/// RegionProblem::make repeats for each.
struct Prepared {
  std::shared_ptr<const backend::RegionSetup> setup;
  backend::Labels labels = backend::Labels::plain;
  RegionPixel classify(Vec2 p) const { return backend::to_pixel(backend::classify_position(*setup, p), labels); }
};

std::vector<Prepared> prepare_many(const BSpline& spline, const std::vector<RegionRequest>& requests) {
  std::vector<Prepared> out;
  std::shared_ptr<const backend::RegionBase> base;
  for (const RegionRequest& r : requests) {
    if (base && base->max_depth != r.max_depth) base.reset();  // a base is one depth's
    if (!base) base = backend::region_base(spline, r.max_depth);
    out.push_back(Prepared{std::make_shared<const backend::RegionSetup>(backend::prepare_region(spline, r, base)),
                           backend::labels_of(r)});
  }
  return out;
}

double unit_cost(const Unit& u, Vec2 x) { return dot(x, x) * static_cast<double>(u.points.size()); }

}  // namespace

FixResult fix(const BSpline& spline, const FixRequest& request_in) {
  const auto start = Clock::now();
  FixRequest request = request_in;  // each-run: each-piece with the nodes as cuts
  request.requirement = resolve_requirement(spline, request_in.requirement);
  const int m = spline.unique_point_count();
  if (!(request.tolerance > 0 && request.tolerance < 1))
    throw InputError("--tolerance: " + std::to_string(request.tolerance) + " is outside (0, 1)");
  if (!(request.max_move >= 0) || !std::isfinite(request.max_move))
    throw InputError("--max-move: " + std::to_string(request.max_move) + " is not a distance >= 0");
  if (!(request.max_seconds >= 0) || !std::isfinite(request.max_seconds))
    throw InputError("--max-seconds: " + std::to_string(request.max_seconds) + " is not a time >= 0");
  if (request.grid < 8 || request.grid > 512) throw InputError("grid " + std::to_string(request.grid) + " is outside 8..512");
  if (request.max_depth < 0 || request.max_depth > kMaxDepth)
    throw InputError("--depth: " + std::to_string(request.max_depth) + " is outside 0.." + std::to_string(kMaxDepth));
  if (request.requirement.kind == FixRequirement::Kind::split &&
      (request.requirement.split < 1 || request.requirement.split > spline.segment_count() - 1))
    throw InputError("--require: split " + std::to_string(request.requirement.split) + " is outside 1.." +
                     std::to_string(spline.segment_count() - 1) + " (the joints of a " +
                     std::to_string(spline.segment_count()) + "-segment spline)");
  std::set<int> given;
  for (int k : request.points) {
    if (k < 0 || k >= m) throw InputError("--points: P" + std::to_string(k) + " is outside 0.." + std::to_string(m - 1));
    if (!given.insert(k).second) throw InputError("--points: P" + std::to_string(k) + " is named twice");
  }

  FixResult out;
  out.size = curve_size(spline);
  const AnalyzeOptions ao = fix_analyze_options(request.requirement, request.max_depth);
  const SplineAnalysis a0 = analyze(spline, ao);
  auto finish = [&](FixResult& r) {
    r.certificate = analyze(*r.spline, ao);
    r.certificate_holds = request.judge ? request.judge(*r.spline) == 0 : requirement_holds(r.certificate, request.requirement);
    // Every tie joint is still G1, and with keep g2 still G2 where it was.
    const std::vector<Joint> before = all_joints(a0), after = all_joints(r.certificate);
    r.ties_hold = true;
    for (int ji : r.tie_joints)
      for (std::size_t i = 0; i < after.size(); ++i)
        if (after[i].index == ji)
          r.ties_hold = r.ties_hold && after[i].g1 && (request.keep != Keep::g2 || !before[i].g2 || after[i].g2);
    r.fixed = r.certificate_holds && r.ties_hold;
    if (!r.fixed && r.reason.empty())
      r.reason = !r.certificate_holds ? "the certificate does not hold" : "a tie at a joint broke";
    r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  };
  if (request.judge ? request.judge(spline) == 0 : requirement_holds(a0, request.requirement)) {
    out.already = true;
    out.spline = spline;
    finish(out);
    return out;
  }
  out.failing_segments = failing_segments(spline, a0, request.requirement);
  if (request.judge) {  // the caller's judge says whether, not where: every judged segment
    out.failing_segments.clear();
    for (int i = a0.range.first; i <= a0.range.last; ++i) out.failing_segments.push_back(i);
  }
  std::set<int> acting;
  for (int i : out.failing_segments)
    for (int k : segment_points(spline, spline.segments()[i])) acting.insert(k);
  std::vector<int> allowed = request.points;
  if (allowed.empty()) {
    for (int k = 0; k < m; ++k)
      if (spline.closed() || (k != 0 && k != m - 1)) allowed.push_back(k);
  } else {
    for (int k : allowed)
      if (!acting.count(k)) {
        std::string segs;
        for (int i : out.failing_segments) segs += (segs.empty() ? "" : ", ") + std::to_string(i);
        throw InputError("--points: P" + std::to_string(k) + " does not act on a failing segment (failing: " + segs + ")");
      }
  }
  // Units of every allowed point: those acting on a failing segment are
  // tried alone; the others join the several-unit search (a segment that
  // fails only by its direction may need its neighbours moved).
  std::set<int> all_points;
  for (int k = 0; k < m; ++k) all_points.insert(k);
  const Ties ties = build_units(spline, a0, allowed, request.keep, all_points);
  auto unit_acts = [&](const Unit& u) {
    return std::any_of(u.points.begin(), u.points.end(), [&](int k) { return acting.count(k) > 0; });
  };
  out.tie_joints = ties.joints;
  out.spline = spline;
  if (std::none_of(ties.units.begin(), ties.units.end(), unit_acts)) {
    out.reason = "no point may move: every point acting on a failing segment is fixed or held by a tie";
    out.nothing_moves = true;
    finish(out);
    return out;
  }

  Search search(spline, request, a0);
  search.handles = ties.handles;
  search.size = out.size;
  search.tol = request.tolerance * out.size;
  search.max_move = request.max_move > 0 ? request.max_move : out.size;
  search.deadline = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(request.max_seconds));
  const FixRequirement::Kind kind = request.requirement.kind;
  const bool region_kind = !local_kind(kind);
  // no-inflection, g2: no region problem; each check is judged exactly on the moved spline.
  const bool exact_local = local_kind(kind) && kind != FixRequirement::Kind::extrema_at_nodes;
  // The checks a unit acts on.
  auto touched_checks = [&](const BSpline& current, const Unit& u) {
    std::vector<int> out_checks;
    for (int i = a0.range.first; i <= a0.range.last; ++i) {
      const std::vector<int> pts = check_points(current, kind, i);
      if (std::any_of(u.points.begin(), u.points.end(),
                      [&](int k) { return std::find(pts.begin(), pts.end(), k) != pts.end(); }))
        out_checks.push_back(i);
    }
    return out_checks;
  };


  // The region requests of the judged segments a unit acts on, each judged
  // alone (extrema-at-nodes: every segment monotone on its own).
  auto segment_requests = [&](const BSpline& current, const Unit& u) {
    std::vector<RegionRequest> rs;
    for (int i = a0.range.first; i <= a0.range.last; ++i) {
      const std::vector<int> pts = segment_points(current, current.segments()[i]);
      const bool touched = std::any_of(u.points.begin(), u.points.end(),
                                       [&](int k) { return std::find(pts.begin(), pts.end(), k) != pts.end(); });
      if (!touched) continue;
      RegionRequest rr;
      rr.point = u.points[0];
      rr.with.assign(u.points.begin() + 1, u.points.end());
      rr.mode = Mode::cmrwi;
      rr.segments = SegmentRange{i, i};
      rr.max_depth = request.max_depth;
      rr.depth = false;
      rs.push_back(std::move(rr));
    }
    return rs;
  };
  // A judged segment the unit does not act on fails in the input: moving the
  // unit alone cannot meet extrema-at-nodes.
  auto hopeless_alone = [&](const Unit& u) {
    for (int i = a0.range.first; i <= a0.range.last; ++i) {
      const std::vector<int> pts = check_points(spline, kind, i);
      const bool touched = std::any_of(u.points.begin(), u.points.end(),
                                       [&](int k) { return std::find(pts.begin(), pts.end(), k) != pts.end(); });
      if (!touched && search.base_bad[i]) return true;
    }
    return false;
  };
  // The problems of several units' requests on one spline, which is analysed
  // once for all of them (prepare_many; that analysis is most of a
  // problem's set-up on a long contour).
  auto problems_of = [&](const BSpline& current, const std::vector<std::vector<RegionRequest>>& per_unit) {
    std::vector<RegionRequest> all;
    for (const auto& rs : per_unit) all.insert(all.end(), rs.begin(), rs.end());
    const std::vector<Prepared> made = prepare_many(current, all);
    std::vector<std::vector<Prepared>> out_problems(per_unit.size());
    std::size_t next = 0;
    for (std::size_t ui = 0; ui < per_unit.size(); ++ui)
      for (std::size_t r = 0; r < per_unit[ui].size(); ++r) out_problems[ui].push_back(made[next++]);
    return out_problems;
  };

  // 1. Each unit alone.
  std::optional<std::size_t> best_unit;
  std::vector<Nearest> alone(ties.units.size());
  std::vector<char> hopeless(ties.units.size(), 0);
  std::vector<std::vector<RegionRequest>> alone_requests(ties.units.size());
  for (std::size_t ui = 0; ui < ties.units.size(); ++ui) {
    const Unit& u = ties.units[ui];
    if (!unit_acts(u)) continue;
    if (region_kind && !request.judge) {
      RegionRequest rr;
      rr.point = u.points[0];
      rr.with.assign(u.points.begin() + 1, u.points.end());
      rr.mode = request.requirement.kind == FixRequirement::Kind::cmr ? Mode::cmr : Mode::cmrwi;
      if (request.requirement.kind == FixRequirement::Kind::split) rr.split = request.requirement.split;
      // each-piece: the region where every piece is monotone on its own, not
      // the (smaller) one where the whole curve is.
      rr.each_piece = request.requirement.kind == FixRequirement::Kind::each_piece;
      if (rr.each_piece) rr.splits = request.requirement.cuts;  // each-run: the groups between the nodes
      rr.segments = request.requirement.segments;                // the judged range only
      rr.max_depth = request.max_depth;
      rr.depth = false;
      alone_requests[ui].push_back(std::move(rr));
    } else if (!region_kind && !(hopeless[ui] = hopeless_alone(u)) && !exact_local) {
      alone_requests[ui] = segment_requests(spline, u);
    }
  }
  const std::vector<std::vector<Prepared>> alone_problems = problems_of(spline, alone_requests);
  for (std::size_t ui = 0; ui < ties.units.size(); ++ui) {
    const Unit& u = ties.units[ui];
    if (!unit_acts(u)) continue;
    if (hopeless[ui]) {
      // extrema-at-nodes: a failing segment the unit does not act on rules it out.
      out.units.push_back(UnitFix{u.points, u.slide, false, Vec2(0.0), 0});
      continue;
    }
    // The unit must make its region problem pass (extrema-at-nodes: every
    // segment it acts on monotone on its own, the region of each judged alone).
    const std::vector<Prepared>& pieces = alone_problems[ui];
    const Vec2 p0 = spline.points()[u.points[0]];
    const std::vector<int> checks = exact_local ? touched_checks(spline, u) : std::vector<int>{};
    const std::function<bool(Vec2)> pass = [&, p0](Vec2 x) {
      ++search.evaluations;
      if (search.expired()) return false;
      if (exact_local || u.slide || request.judge) {
        std::vector<Vec2> d(m, Vec2(0.0));
        for (int k : u.points) d[k] += x;
        if (exact_local) return search.bad_in(d, checks) == 0;
        if (search.flips(d)) return false;
        if (request.judge) return request.judge(search.moved(d)) == 0;
      }
      for (const Prepared& pr : pieces)
        if (!passing_pixel(pr.classify(p0 + x), request.requirement)) return false;
      return true;
    };
    // The region labels (cmr: the paper's Algorithm 2) may pass a position
    // the certificate (analyze: exact inflections) fails, in slivers along
    // an edge: the answer is the nearest candidate the requirement accepts.
    // Cheap certified labels (the region problems; curvature-extrema-at-nodes:
    // each segment's own): search below the first cell.
    const bool refine = !exact_local && !request.judge;
    const std::function<bool(Vec2)> certify = [&](Vec2 x) {
      std::vector<Vec2> d(m, Vec2(0.0));
      for (int k : u.points) d[k] += x;
      return search.holds(d);
    };
    // The exactly judged kinds (no region problem: each position re-judges
    // its checks in exact arithmetic) search half the grid from two seeds.
    alone[ui] = exact_local ? nearest(pass, u.dims(), u.dir, out.size, search.max_move, search.tol,
                                      std::max(8, request.grid / 2), request.threads, 2)
                            : nearest(pass, u.dims(), u.dir, out.size, search.max_move, search.tol, request.grid,
                                      request.threads, 6, refine, refine ? certify : std::function<bool(Vec2)>{});
    UnitFix uf;
    uf.points = u.points;
    uf.slide = u.slide;
    uf.found = alone[ui].found;
    uf.displacement = alone[ui].x;
    uf.distance = alone[ui].dist;
    out.units.push_back(uf);
    if (alone[ui].found &&
        (!best_unit || unit_cost(u, alone[ui].x) < unit_cost(ties.units[*best_unit], alone[*best_unit].x)))
      best_unit = ui;
  }

  // The state of the several-unit search: one coordinate block per unit.
  std::vector<std::size_t> offset(ties.units.size() + 1, 0);
  for (std::size_t ui = 0; ui < ties.units.size(); ++ui) offset[ui + 1] = offset[ui] + ties.units[ui].dims();
  auto delta_of = [&](const std::vector<double>& z) {
    std::vector<Vec2> delta(m, Vec2(0.0));
    for (std::size_t ui = 0; ui < ties.units.size(); ++ui) {
      const Unit& u = ties.units[ui];
      const Vec2 x = u.slide ? z[offset[ui]] * u.dir : Vec2(z[offset[ui]], z[offset[ui] + 1]);
      for (int k : u.points) delta[k] += x;
    }
    return delta;
  };
  auto cost_of = [&](const std::vector<double>& z) {
    double c = 0;
    for (const Vec2& d : delta_of(z)) c += dot(d, d);
    return c;
  };
  auto set_unit = [&](std::vector<double>& z, std::size_t ui, Vec2 x) {
    if (ties.units[ui].slide)
      z[offset[ui]] = dot(x, ties.units[ui].dir);
    else
      z[offset[ui]] = x.x, z[offset[ui] + 1] = x.y;
  };
  // Two units moved at once, for a greedy step that no single unit can
  // make: every pair of units acting on a common failing segment, each
  // pair's nearest position (in coordinates scaled so that their squared
  // length is the added squared displacement) that lowers the badness
  // (extrema-at-nodes: fewer of the segments the pair acts on fail, each
  // classified again exactly); the cheapest pair's moves.
  auto two_at_once = [&](const std::vector<Vec2>& now, const BSpline& current, int before) {
    std::vector<std::pair<std::size_t, Vec2>> best_moves;
    double best_cost = std::numeric_limits<double>::infinity();
    std::vector<int> failing;
    if (!region_kind) {
      for (int i = a0.range.first; i <= a0.range.last; ++i)
        if (search.bad_in(now, {i})) failing.push_back(i);
    } else {
      failing = request.judge ? out.failing_segments
                              : failing_segments(current, analyze(current, ao), request.requirement);
    }
    auto touches = [&](const Unit& u, int i) {
      const std::vector<int> pts = check_points(current, kind, i);
      return std::any_of(u.points.begin(), u.points.end(),
                         [&](int k) { return std::find(pts.begin(), pts.end(), k) != pts.end(); });
    };
    std::set<std::pair<std::size_t, std::size_t>> pairs;
    for (int i : failing) {
      std::vector<std::size_t> on;
      for (std::size_t ui = 0; ui < ties.units.size(); ++ui)
        if (touches(ties.units[ui], i)) on.push_back(ui);
      for (std::size_t p = 0; p < on.size(); ++p)
        for (std::size_t q = p + 1; q < on.size(); ++q) pairs.insert({on[p], on[q]});
    }
    std::vector<std::pair<std::size_t, std::size_t>> order(pairs.begin(), pairs.end());
    std::stable_sort(order.begin(), order.end(), [&](const auto& p, const auto& q) {
      return ties.units[p.first].dims() + ties.units[p.second].dims() <
             ties.units[q.first].dims() + ties.units[q.second].dims();
    });  // the cheap 2-D pairs first: their distance bounds the others' search
    for (const auto& [a, b] : order) {
      if (search.expired()) break;
      const Unit& ua = ties.units[a];
      const Unit& ub = ties.units[b];
      std::vector<int> segs;
      int local_before = 0;
      for (int i = a0.range.first; i <= a0.range.last; ++i)
        if (touches(ua, i) || touches(ub, i)) {
          segs.push_back(i);
          local_before += std::binary_search(failing.begin(), failing.end(), i);
        }
      const int da = ua.dims(), dims = da + ub.dims();
      const double wa = 1 / std::sqrt(static_cast<double>(ua.points.size()));
      const double wb = 1 / std::sqrt(static_cast<double>(ub.points.size()));
      auto moves_of = [&](const std::vector<double>& c) {
        const Vec2 xa = wa * (ua.slide ? c[0] * ua.dir : Vec2(c[0], c[1]));
        const Vec2 xb = wb * (ub.slide ? c[da] * ub.dir : Vec2(c[da], c[da + 1]));
        return std::pair{xa, xb};
      };
      const std::function<bool(const std::vector<double>&)> pass_n = [&](const std::vector<double>& c) {
        const auto [xa, xb] = moves_of(c);
        std::vector<Vec2> d = now;
        for (int k : ua.points) d[k] += xa;
        for (int k : ub.points) d[k] += xb;
        if (region_kind) return search.badness(d) < before;
        ++search.evaluations;
        if (search.expired()) return false;
        for (const Vec2& dk : d)
          if (norm(dk) > search.max_move) return false;
        return search.bad_in(d, segs) < local_before;
      };
      const double coarse = std::max(search.tol, 1e-3 * out.size);
      // A pair farther than the best so far cannot win: search only inside it.
      const double reach = std::min(search.max_move * std::sqrt(static_cast<double>(dims)), std::sqrt(best_cost));
      std::vector<double> c;
      if (dims == 2) {
        const Nearest nr = nearest([&](Vec2 x) { return pass_n({x.x, x.y}); }, 2, Vec2(0.0), out.size, reach, coarse,
                                   std::max(8, request.grid / 2), request.threads, 1);
        if (nr.found) c = {nr.x.x, nr.x.y};
      } else {
        const NearestN nr = nearest_rays(pass_n, dims, out.size, reach, coarse, request.threads);
        if (nr.found) c = nr.c;
      }
      if (c.empty()) continue;
      double cost = 0;
      for (double v : c) cost += v * v;
      if (cost < best_cost) {
        best_cost = cost;
        const auto [xa, xb] = moves_of(c);
        best_moves = {{a, xa}, {b, xb}};
      }
    }
    return best_moves;
  };
  std::vector<double> z(offset.back(), 0.0);
  bool feasible = false;
  if (best_unit) {
    set_unit(z, *best_unit, alone[*best_unit].x);
    feasible = true;
  }
  if (!feasible) {
    // 2a. Greedy: each step moves one unit to the nearest position that
    // lowers the badness (Search::badness) of the curve.
    // extrema-at-nodes judges each unit on its own segments only, so a
    // unit's step (cached) stays valid until a point of those segments moves.
    std::vector<std::optional<Nearest>> cached(ties.units.size());
    std::vector<std::vector<int>> watch(ties.units.size());  // points of the segments a unit acts on
    if (!region_kind)
      for (std::size_t ui = 0; ui < ties.units.size(); ++ui) {
        std::set<int> w(ties.units[ui].points.begin(), ties.units[ui].points.end());
        for (int i = a0.range.first; i <= a0.range.last; ++i) {
          const std::vector<int> pts = check_points(spline, kind, i);
          const bool touched = std::any_of(ties.units[ui].points.begin(), ties.units[ui].points.end(), [&](int k) {
            return std::find(pts.begin(), pts.end(), k) != pts.end();
          });
          if (touched) w.insert(pts.begin(), pts.end());
        }
        watch[ui].assign(w.begin(), w.end());
      }
    for (int step = 0; step < static_cast<int>(ties.units.size()) && !feasible; ++step) {
      std::optional<std::pair<std::size_t, Vec2>> pick;
      double pick_cost = std::numeric_limits<double>::infinity();
      const std::vector<Vec2> now = delta_of(z);
      const int before = search.badness(now);
      const BSpline current = search.moved(now);
      // extrema-at-nodes: the region problems of every unit without a cached
      // step, on the current spline (analysed once for all of them).
      std::vector<std::vector<RegionRequest>> step_requests(ties.units.size());
      if (!region_kind && !exact_local)
        for (std::size_t ui = 0; ui < ties.units.size(); ++ui)
          if (!cached[ui]) step_requests[ui] = segment_requests(current, ties.units[ui]);
      const std::vector<std::vector<Prepared>> step_problems = problems_of(current, step_requests);
      for (std::size_t ui = 0; ui < ties.units.size(); ++ui) {
        const Unit& u = ties.units[ui];
        if (cached[ui]) {
          const Nearest& nr = *cached[ui];
          if (nr.found && unit_cost(u, nr.x) < pick_cost) pick_cost = unit_cost(u, nr.x), pick = std::make_pair(ui, nr.x);
          continue;
        }
        std::function<bool(Vec2)> pass = [&](Vec2 x) {
          std::vector<Vec2> d = now;
          for (int k : u.points) d[k] += x;
          return search.badness(d) < before;
        };
        // extrema-at-nodes: fewer of the unit's own segments fail, judged by
        // their regions on the current spline.
        const std::vector<Prepared>& pieces = step_problems[ui];
        int bad_now = 0;
        const Vec2 p0 = current.points()[u.points[0]];
        const std::vector<int> checks = exact_local ? touched_checks(current, u) : std::vector<int>{};
        if (exact_local) bad_now = search.bad_in(now, checks);
        if (!region_kind) {
          if (!exact_local)
            for (const Prepared& pr : pieces) bad_now += !passing_pixel(pr.classify(p0), request.requirement);
          if (bad_now == 0) {
            cached[ui] = Nearest{};
            continue;
          }
          pass = [&, p0, bad_now](Vec2 x) {
            ++search.evaluations;
            if (search.expired()) return false;
            for (int k : u.points)
              if (norm(now[k] + x) > search.max_move) return false;
            if (exact_local || u.slide) {
              std::vector<Vec2> d = now;
              for (int k : u.points) d[k] += x;
              if (exact_local) return search.bad_in(d, checks) < bad_now;
              if (search.flips(d)) return false;
            }
            int bad = 0;
            for (const Prepared& pr : pieces) bad += !passing_pixel(pr.classify(p0 + x), request.requirement);
            return bad < bad_now;
          };
        }
        // Coarse (half the grid, 1e-3 of the size, one seed): the compass search refines.
        const Nearest nr = nearest(pass, u.dims(), u.dir, out.size, search.max_move, std::max(search.tol, 1e-3 * out.size),
                                   std::max(8, request.grid / 2), request.threads, 1);
        if (!region_kind && !search.timed_out) cached[ui] = nr;
        if (nr.found && unit_cost(u, nr.x) < pick_cost) pick_cost = unit_cost(u, nr.x), pick = std::make_pair(ui, nr.x);
      }
      // No single unit lowers the badness (with G1 kept a segment whose two
      // handles must both slide, or a node group that must move with a
      // handle): two units at once.
      std::vector<std::pair<std::size_t, Vec2>> step_moves;
      if (pick)
        step_moves.push_back(*pick);
      else if (!search.expired())
        step_moves = two_at_once(now, current, before);
      if (step_moves.empty()) break;
      for (const auto& [pu, x] : step_moves) {
        const Unit& u = ties.units[pu];
        const Vec2 x0 = u.slide ? z[offset[pu]] * u.dir : Vec2(z[offset[pu]], z[offset[pu] + 1]);
        set_unit(z, pu, x0 + x);
        for (std::size_t ui = 0; ui < ties.units.size(); ++ui)
          for (int k : u.points)
            if (std::binary_search(watch[ui].begin(), watch[ui].end(), k)) cached[ui].reset();
      }
      feasible = search.holds(delta_of(z));
    }
  }
  if (feasible && (request.together || !best_unit)) {
    // 2b. Compass search on the total squared displacement; each trial is
    // pulled back towards no move by bisection while it still passes.
    auto ok = [&](const std::vector<double>& v) { return search.holds(delta_of(v)); };
    const double stop = std::max(search.tol, 1e-3 * out.size);
    auto project = [&](std::vector<double> v, double precision) {
      double lo = 0, hi = 1;
      double len = std::sqrt(cost_of(v));
      while ((hi - lo) * len > precision) {
        const double mid = 0.5 * (lo + hi);
        std::vector<double> t = v;
        for (double& c : t) c *= mid;
        if (ok(t)) hi = mid; else lo = mid;
      }
      for (double& c : v) c *= hi;
      return v;
    };
    std::vector<bool> moved_coordinate(z.size(), false);
    for (std::size_t ui = 0; ui < ties.units.size(); ++ui)
      for (std::size_t i = offset[ui]; i < offset[ui + 1]; ++i)
        for (std::size_t c = offset[ui]; c < offset[ui + 1]; ++c) moved_coordinate[i] = moved_coordinate[i] || z[c] != 0;
    z = project(z, stop / 4);
    double h = std::max(std::sqrt(cost_of(z)) / 2, stop);
    const int rounds = request.together ? 200 : 20;  // after greedy steps: a short polish
    for (int round = 0; round < rounds && h >= stop; ++round) {
      bool improved = false;
      for (std::size_t i = 0; i < z.size() && !improved; ++i)
        for (const double sgn : {-1.0, 1.0}) {
          if (!request.together && !moved_coordinate[i]) continue;  // only the units the greedy steps moved
          std::vector<double> t = z;
          t[i] += sgn * h;
          if (!ok(t)) continue;
          t = project(t, stop / 4);
          if (cost_of(t) < cost_of(z) * (1 - 1e-9)) {
            z = t;
            improved = true;
            break;
          }
        }
      if (!improved) h /= 2;
    }
    z = project(z, search.tol / 8);  // the last pull to the tolerance
  }
  if (!feasible) {
    out.reason = search.timed_out ? "no certified fix found in the time limit (" + std::to_string(request.max_seconds) + " s)"
                                  : "no certified fix within --max-move " + std::to_string(search.max_move) + " (" +
                                        std::to_string(ties.units.size()) + " unit(s) of motion tried)";
    out.evaluations = search.evaluations;
    finish(out);
    return out;
  }
  const std::vector<Vec2> delta = delta_of(z);
  out.spline = search.moved(delta);
  for (int k = 0; k < m; ++k) {
    if (delta[k] == Vec2(0.0)) continue;
    PointMove pm{k, spline.points()[k], out.spline->points()[k], norm(out.spline->points()[k] - spline.points()[k])};
    out.total_squared += pm.distance * pm.distance;
    out.max_distance = std::max(out.max_distance, pm.distance);
    out.moves.push_back(pm);
  }
  out.evaluations = search.evaluations;
  finish(out);
  return out;
}

}  // namespace cmr
