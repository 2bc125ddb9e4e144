#include "design/fix.hpp"
#include "design/fix_detail.hpp"

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

#include "numeric/bernstein.hpp"
#include "numeric/bounded.hpp"
#include "bezierize/extract.hpp"
#include "bezierize/lambda.hpp"
#include "region/region.hpp"
#include "region/region_setup.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/parallel.hpp"

// The nearest certified repair (fix.hpp): the requirement and its checks, and
// fix() itself. The parts of its search (units of points, local judges, the
// nearest passing displacement) are in fix_search.cpp.

namespace cmr {

using namespace fix_detail;  // what the parts share (fix_detail.hpp)

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
      throw InputFieldError(field("requirement") + ": '" + text +
                            "' needs a relative tolerance >= 0 (g2-at-smooth-nodes:0.05)");
    }
  }
  if (text.rfind("split:", 0) == 0) {
    std::string s = text.substr(6);
    r.kind = FixRequirement::Kind::split;
    const std::size_t colon = s.find(':');
    if (colon != std::string::npos) {
      const std::string e = s.substr(colon + 1);
      if (e == "max" || e == "min")
        throw InputFieldError(
            field("requirement") + ": '" + text +
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
  throw InputFieldError(
      field("requirement") + ": '" + text +
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

namespace fix_detail {

double norm(Vec2 v) { return std::sqrt(dot(v, v)); }

}  // namespace fix_detail

namespace {

bool monotone(Direction d) { return d == Direction::increasing || d == Direction::decreasing; }

}  // namespace

namespace fix_detail {

bool monotone_class(const SegmentClass& c) {
  const Curvature k = c.monotonicity.curvature;
  return k == Curvature::increasing || k == Curvature::decreasing || k == Curvature::constant;
}

}  // namespace fix_detail

namespace {

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

namespace {

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
    throw InputFieldError(field("tolerance") + ": " + std::to_string(request.tolerance) + " is outside (0, 1)");
  if (!(request.max_move >= 0) || !std::isfinite(request.max_move))
    throw InputFieldError(field("max_move") + ": " + std::to_string(request.max_move) + " is not a distance >= 0");
  if (!(request.max_seconds >= 0) || !std::isfinite(request.max_seconds))
    throw InputFieldError(field("max_seconds") + ": " + std::to_string(request.max_seconds) + " is not a time >= 0");
  if (request.grid < 8 || request.grid > 512) throw InputError("grid " + std::to_string(request.grid) + " is outside 8..512");
  if (request.max_depth < 0 || request.max_depth > kMaxDepth)
    throw InputFieldError(field("max_depth") + ": " + std::to_string(request.max_depth) + " is outside 0.." +
                          std::to_string(kMaxDepth));
  if (request.requirement.kind == FixRequirement::Kind::split &&
      (request.requirement.split < 1 || request.requirement.split > spline.segment_count() - 1))
    throw InputFieldError(field("requirement") + ": split " + std::to_string(request.requirement.split) +
                          " is outside 1.." + std::to_string(spline.segment_count() - 1) + " (the joints of a " +
                          std::to_string(spline.segment_count()) + "-segment spline)");
  std::set<int> given;
  for (int k : request.points) {
    if (k < 0 || k >= m)
      throw InputFieldError(field("points") + ": P" + std::to_string(k) + " is outside 0.." + std::to_string(m - 1));
    if (!given.insert(k).second) throw InputFieldError(field("points") + ": P" + std::to_string(k) + " is named twice");
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
        throw InputFieldError(field("points") + ": P" + std::to_string(k) +
                              " does not act on a failing segment (failing: " + segs + ")");
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
    out.reason = search.timed_out
                     ? "no certified fix found in the time limit (" + std::to_string(request.max_seconds) + " s)"
                     : "no certified fix within " + field("max_move") + " " + std::to_string(search.max_move) + " (" +
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
