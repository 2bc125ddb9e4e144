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
#include "spline/format.hpp"
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

namespace {

/// The request's numbers and points, checked before any work
/// (InputFieldError naming the field).
void check_fix_request(const BSpline& spline, const FixRequest& request) {
  const int m = spline.unique_point_count();
  if (!(request.tolerance > 0 && request.tolerance < 1))
    throw InputFieldError(field("tolerance") + ": " + std::to_string(request.tolerance) + " is outside (0, 1)");
  if (!(request.max_move >= 0) || !std::isfinite(request.max_move))
    throw InputFieldError(field("max_move") + ": " + format_number(request.max_move) + " is not a distance >= 0");
  if (!(request.max_seconds >= 0) || !std::isfinite(request.max_seconds))
    throw InputFieldError(field("max_seconds") + ": " + std::to_string(request.max_seconds) + " is not a time >= 0");
  if (request.max_evaluations < 0)
    throw InputError("max_evaluations " + std::to_string(request.max_evaluations) + " is negative");
  if (request.thread_cpu_clock && request.threads != 1)
    throw InputError("a limit on the thread's CPU clock needs a search on one thread (threads 1, not " +
                     std::to_string(request.threads) + ")");
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
}

/// One run of fix(): the input's analysis, the units of motion and the
/// search's state, shared by its stages:
///   1. each unit alone (each_unit_alone): the nearest position of each unit
///      that meets the requirement by itself; the cheapest one wins;
///   2a. otherwise greedy steps (greedy): one unit (or two at once,
///      two_at_once) moved at a time to lower the badness until it holds;
///   2b. then a compass search (polish) on the total squared displacement.
/// Every answer is certified (certify) before it is returned.
class FixRun {
 public:
  /// `unit`: the caller's length of one of the spline's units (messages
  /// give lengths in the caller's units: fix() scales far-off curves).
  FixRun(const BSpline& spline, const FixRequest& request_in, Clock::time_point start, double unit = 1)
      : spline_(spline), request_(request_in), start_(start), m_(spline.unique_point_count()), unit_(unit) {
    request_.requirement = resolve_requirement(spline, request_in.requirement);  // each-run: each-piece with the nodes as cuts
    check_fix_request(spline, request_);
    out_.size = curve_size(spline);
    ao_ = fix_analyze_options(request_.requirement, request_.max_depth);
    a0_ = analyze(spline, ao_);
    kind_ = request_.requirement.kind;
    region_kind_ = !local_kind(kind_);
    // no-inflection, g2: no region problem; each check is judged exactly on the moved spline.
    exact_local_ = local_kind(kind_) && kind_ != FixRequirement::Kind::extrema_at_nodes;
  }

  /// The answer (once: it is moved out of the run).
  FixResult run();

 private:
  bool judged_to_hold(const BSpline& s, const SplineAnalysis& a) const {
    return request_.judge ? request_.judge(s) == 0 : requirement_holds(a, request_.requirement);
  }
  void certify(FixResult& r) const;
  std::vector<int> allowed_points() const;
  bool unit_acts(const Unit& u) const {
    return std::any_of(u.points.begin(), u.points.end(), [&](int k) { return acting_.count(k) > 0; });
  }
  std::vector<int> touched_checks(const BSpline& current, const Unit& u) const;
  std::vector<RegionRequest> segment_requests(const BSpline& current, const Unit& u) const;
  bool hopeless_alone(const Unit& u) const;
  std::vector<std::vector<Prepared>> problems_of(const BSpline& current,
                                                 const std::vector<std::vector<RegionRequest>>& per_unit) const;
  void each_unit_alone();
  std::vector<Vec2> delta_of(const std::vector<double>& z) const;
  double cost_of(const std::vector<double>& z) const {
    double c = 0;
    for (const Vec2& d : delta_of(z)) c += dot(d, d);
    return c;
  }
  void set_unit(std::vector<double>& z, std::size_t ui, Vec2 x) const {
    if (ties_.units[ui].slide)
      z[offset_[ui]] = dot(x, ties_.units[ui].dir);
    else
      z[offset_[ui]] = x.x, z[offset_[ui] + 1] = x.y;
  }
  std::vector<std::pair<std::size_t, Vec2>> two_at_once(const std::vector<Vec2>& now, const BSpline& current,
                                                        int before);
  bool greedy(std::vector<double>& z);
  void polish(std::vector<double>& z);

  const BSpline& spline_;
  FixRequest request_;
  const Clock::time_point start_;
  const int m_;
  const double unit_;
  FixResult out_;
  AnalyzeOptions ao_;
  SplineAnalysis a0_;
  FixRequirement::Kind kind_{};
  bool region_kind_ = false, exact_local_ = false;
  std::set<int> acting_;  ///< points acting on a failing segment
  Ties ties_;
  std::optional<Search> search_;  ///< made once the units are known
  // Stage 1's answers, per unit.
  std::vector<Nearest> alone_;
  std::optional<std::size_t> best_unit_;
  // The several-unit search: one coordinate block per unit.
  std::vector<std::size_t> offset_;
};

void FixRun::certify(FixResult& r) const {
  r.certificate = analyze(*r.spline, ao_);
  r.certificate_holds = judged_to_hold(*r.spline, r.certificate);
  // Every tie joint is still G1, and with keep g2 still G2 where it was.
  const std::vector<Joint> before = all_joints(a0_), after = all_joints(r.certificate);
  r.ties_hold = true;
  for (int ji : r.tie_joints)
    for (std::size_t i = 0; i < after.size(); ++i)
      if (after[i].index == ji)
        r.ties_hold = r.ties_hold && after[i].g1 && (request_.keep != Keep::g2 || !before[i].g2 || after[i].g2);
  r.fixed = r.certificate_holds && r.ties_hold;
  if (!r.fixed && r.reason.empty())
    r.reason = !r.certificate_holds ? "the certificate does not hold" : "a tie at a joint broke";
  r.seconds = std::chrono::duration<double>(Clock::now() - start_).count();
}

/// The points that may move: the request's (each must act on a failing
/// segment), else every point but an open curve's two ends.
std::vector<int> FixRun::allowed_points() const {
  std::vector<int> allowed = request_.points;
  if (allowed.empty()) {
    for (int k = 0; k < m_; ++k)
      if (spline_.closed() || (k != 0 && k != m_ - 1)) allowed.push_back(k);
    return allowed;
  }
  for (int k : allowed)
    if (!acting_.count(k)) {
      std::string segs;
      for (int i : out_.failing_segments) segs += (segs.empty() ? "" : ", ") + std::to_string(i);
      throw InputFieldError(field("points") + ": P" + std::to_string(k) +
                            " does not act on a failing segment (failing: " + segs + ")");
    }
  return allowed;
}

/// The checks a unit acts on.
std::vector<int> FixRun::touched_checks(const BSpline& current, const Unit& u) const {
  std::vector<int> out_checks;
  for (int i = a0_.range.first; i <= a0_.range.last; ++i) {
    const std::vector<int> pts = check_points(current, kind_, i);
    if (std::any_of(u.points.begin(), u.points.end(),
                    [&](int k) { return std::find(pts.begin(), pts.end(), k) != pts.end(); }))
      out_checks.push_back(i);
  }
  return out_checks;
}

/// The region requests of the judged segments a unit acts on, each judged
/// alone (extrema-at-nodes: every segment monotone on its own).
std::vector<RegionRequest> FixRun::segment_requests(const BSpline& current, const Unit& u) const {
  std::vector<RegionRequest> rs;
  for (int i = a0_.range.first; i <= a0_.range.last; ++i) {
    const std::vector<int> pts = segment_points(current, current.segments()[i]);
    const bool touched = std::any_of(u.points.begin(), u.points.end(),
                                     [&](int k) { return std::find(pts.begin(), pts.end(), k) != pts.end(); });
    if (!touched) continue;
    RegionRequest rr;
    rr.point = u.points[0];
    rr.with.assign(u.points.begin() + 1, u.points.end());
    rr.mode = Mode::cmrwi;
    rr.segments = SegmentRange{i, i};
    rr.max_depth = request_.max_depth;
    rr.depth = false;
    rs.push_back(std::move(rr));
  }
  return rs;
}

/// A judged segment the unit does not act on fails in the input: moving the
/// unit alone cannot meet extrema-at-nodes.
bool FixRun::hopeless_alone(const Unit& u) const {
  for (int i = a0_.range.first; i <= a0_.range.last; ++i) {
    const std::vector<int> pts = check_points(spline_, kind_, i);
    const bool touched = std::any_of(u.points.begin(), u.points.end(),
                                     [&](int k) { return std::find(pts.begin(), pts.end(), k) != pts.end(); });
    if (!touched && search_->base_bad[i]) return true;
  }
  return false;
}

/// The problems of several units' requests on one spline, which is analysed
/// once for all of them (prepare_many; that analysis is most of a
/// problem's set-up on a long contour).
std::vector<std::vector<Prepared>> FixRun::problems_of(
    const BSpline& current, const std::vector<std::vector<RegionRequest>>& per_unit) const {
  std::vector<RegionRequest> all;
  for (const auto& rs : per_unit) all.insert(all.end(), rs.begin(), rs.end());
  const std::vector<Prepared> made = prepare_many(current, all);
  std::vector<std::vector<Prepared>> out_problems(per_unit.size());
  std::size_t next = 0;
  for (std::size_t ui = 0; ui < per_unit.size(); ++ui)
    for (std::size_t r = 0; r < per_unit[ui].size(); ++r) out_problems[ui].push_back(made[next++]);
  return out_problems;
}

/// Stage 1: each unit alone. Fills alone_, best_unit_ and out_.units.
void FixRun::each_unit_alone() {
  Search& search = *search_;
  const FixRequest& request = request_;
  alone_.assign(ties_.units.size(), Nearest{});
  std::vector<char> hopeless(ties_.units.size(), 0);
  std::vector<std::vector<RegionRequest>> alone_requests(ties_.units.size());
  for (std::size_t ui = 0; ui < ties_.units.size(); ++ui) {
    const Unit& u = ties_.units[ui];
    if (!unit_acts(u)) continue;
    if (region_kind_ && !request.judge) {
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
    } else if (!region_kind_ && !(hopeless[ui] = hopeless_alone(u)) && !exact_local_) {
      alone_requests[ui] = segment_requests(spline_, u);
    }
  }
  const std::vector<std::vector<Prepared>> alone_problems = problems_of(spline_, alone_requests);
  for (std::size_t ui = 0; ui < ties_.units.size(); ++ui) {
    const Unit& u = ties_.units[ui];
    if (!unit_acts(u)) continue;
    if (hopeless[ui]) {
      // extrema-at-nodes: a failing segment the unit does not act on rules it out.
      out_.units.push_back(UnitFix{u.points, u.slide, false, Vec2(0.0), 0});
      continue;
    }
    // The unit must make its region problem pass (extrema-at-nodes: every
    // segment it acts on monotone on its own, the region of each judged alone).
    const std::vector<Prepared>& pieces = alone_problems[ui];
    const Vec2 p0 = spline_.points()[u.points[0]];
    const std::vector<int> checks = exact_local_ ? touched_checks(spline_, u) : std::vector<int>{};
    const int m = m_;
    const bool exact_local = exact_local_;
    const std::function<bool(Vec2)> pass = [&, p0](Vec2 x) {
      if (!search.count_evaluation()) return false;
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
    const std::function<bool(Vec2)> certify_position = [&](Vec2 x) {
      std::vector<Vec2> d(m, Vec2(0.0));
      for (int k : u.points) d[k] += x;
      return search.holds(d);
    };
    // The exactly judged kinds (no region problem: each position re-judges
    // its checks in exact arithmetic) search half the grid from two seeds.
    alone_[ui] = exact_local ? nearest(pass, u.dims(), u.dir, out_.size, search.max_move, search.tol,
                                       std::max(8, request.grid / 2), request.threads, 2)
                             : nearest(pass, u.dims(), u.dir, out_.size, search.max_move, search.tol, request.grid,
                                       request.threads, 6, refine,
                                       refine ? certify_position : std::function<bool(Vec2)>{});
    UnitFix uf;
    uf.points = u.points;
    uf.slide = u.slide;
    uf.found = alone_[ui].found;
    uf.displacement = alone_[ui].x;
    uf.distance = alone_[ui].dist;
    out_.units.push_back(uf);
    if (alone_[ui].found &&
        (!best_unit_ || unit_cost(u, alone_[ui].x) < unit_cost(ties_.units[*best_unit_], alone_[*best_unit_].x)))
      best_unit_ = ui;
  }
}

std::vector<Vec2> FixRun::delta_of(const std::vector<double>& z) const {
  std::vector<Vec2> delta(m_, Vec2(0.0));
  for (std::size_t ui = 0; ui < ties_.units.size(); ++ui) {
    const Unit& u = ties_.units[ui];
    const Vec2 x = u.slide ? z[offset_[ui]] * u.dir : Vec2(z[offset_[ui]], z[offset_[ui] + 1]);
    for (int k : u.points) delta[k] += x;
  }
  return delta;
}

// Two units moved at once, for a greedy step that no single unit can
// make: every pair of units acting on a common failing segment, each
// pair's nearest position (in coordinates scaled so that their squared
// length is the added squared displacement) that lowers the badness
// (extrema-at-nodes: fewer of the segments the pair acts on fail, each
// classified again exactly); the cheapest pair's moves.
std::vector<std::pair<std::size_t, Vec2>> FixRun::two_at_once(const std::vector<Vec2>& now, const BSpline& current,
                                                              int before) {
  Search& search = *search_;
  const FixRequest& request = request_;
  const bool region_kind = region_kind_;
  std::vector<std::pair<std::size_t, Vec2>> best_moves;
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<int> failing;
  if (!region_kind) {
    for (int i = a0_.range.first; i <= a0_.range.last; ++i)
      if (search.bad_in(now, {i})) failing.push_back(i);
  } else {
    failing = request.judge ? out_.failing_segments
                            : failing_segments(current, analyze(current, ao_), request.requirement);
  }
  auto touches = [&](const Unit& u, int i) {
    const std::vector<int> pts = check_points(current, kind_, i);
    return std::any_of(u.points.begin(), u.points.end(),
                       [&](int k) { return std::find(pts.begin(), pts.end(), k) != pts.end(); });
  };
  std::set<std::pair<std::size_t, std::size_t>> pairs;
  for (int i : failing) {
    std::vector<std::size_t> on;
    for (std::size_t ui = 0; ui < ties_.units.size(); ++ui)
      if (touches(ties_.units[ui], i)) on.push_back(ui);
    for (std::size_t p = 0; p < on.size(); ++p)
      for (std::size_t q = p + 1; q < on.size(); ++q) pairs.insert({on[p], on[q]});
  }
  std::vector<std::pair<std::size_t, std::size_t>> order(pairs.begin(), pairs.end());
  std::stable_sort(order.begin(), order.end(), [&](const auto& p, const auto& q) {
    return ties_.units[p.first].dims() + ties_.units[p.second].dims() <
           ties_.units[q.first].dims() + ties_.units[q.second].dims();
  });  // the cheap 2-D pairs first: their distance bounds the others' search
  for (const auto& [a, b] : order) {
    if (search.expired()) break;
    const Unit& ua = ties_.units[a];
    const Unit& ub = ties_.units[b];
    std::vector<int> segs;
    int local_before = 0;
    for (int i = a0_.range.first; i <= a0_.range.last; ++i)
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
      if (!search.count_evaluation()) return false;
      for (const Vec2& dk : d)
        if (norm(dk) > search.max_move) return false;
      return search.bad_in(d, segs) < local_before;
    };
    const double coarse = std::max(search.tol, 1e-3 * out_.size);
    // A pair farther than the best so far cannot win: search only inside it.
    const double reach = std::min(search.max_move * std::sqrt(static_cast<double>(dims)), std::sqrt(best_cost));
    std::vector<double> c;
    if (dims == 2) {
      const Nearest nr = nearest([&](Vec2 x) { return pass_n({x.x, x.y}); }, 2, Vec2(0.0), out_.size, reach, coarse,
                                 std::max(8, request.grid / 2), request.threads, 1);
      if (nr.found) c = {nr.x.x, nr.x.y};
    } else {
      const NearestN nr = nearest_rays(pass_n, dims, out_.size, reach, coarse, request.threads);
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
}

/// Stage 2a, greedy: each step moves one unit to the nearest position that
/// lowers the badness (Search::badness) of the curve; whether z then holds.
/// extrema-at-nodes judges each unit on its own segments only, so a unit's
/// step (cached) stays valid until a point of those segments moves.
bool FixRun::greedy(std::vector<double>& z) {
  Search& search = *search_;
  const FixRequest& request = request_;
  const bool region_kind = region_kind_, exact_local = exact_local_;
  bool feasible = false;
  std::vector<std::optional<Nearest>> cached(ties_.units.size());
  std::vector<std::vector<int>> watch(ties_.units.size());  // points of the segments a unit acts on
  if (!region_kind)
    for (std::size_t ui = 0; ui < ties_.units.size(); ++ui) {
      std::set<int> w(ties_.units[ui].points.begin(), ties_.units[ui].points.end());
      for (int i = a0_.range.first; i <= a0_.range.last; ++i) {
        const std::vector<int> pts = check_points(spline_, kind_, i);
        const bool touched = std::any_of(ties_.units[ui].points.begin(), ties_.units[ui].points.end(), [&](int k) {
          return std::find(pts.begin(), pts.end(), k) != pts.end();
        });
        if (touched) w.insert(pts.begin(), pts.end());
      }
      watch[ui].assign(w.begin(), w.end());
    }
  for (int step = 0; step < static_cast<int>(ties_.units.size()) && !feasible; ++step) {
    std::optional<std::pair<std::size_t, Vec2>> pick;
    double pick_cost = std::numeric_limits<double>::infinity();
    const std::vector<Vec2> now = delta_of(z);
    const int before = search.badness(now);
    const BSpline current = search.moved(now);
    // extrema-at-nodes: the region problems of every unit without a cached
    // step, on the current spline (analysed once for all of them).
    std::vector<std::vector<RegionRequest>> step_requests(ties_.units.size());
    if (!region_kind && !exact_local)
      for (std::size_t ui = 0; ui < ties_.units.size(); ++ui)
        if (!cached[ui]) step_requests[ui] = segment_requests(current, ties_.units[ui]);
    const std::vector<std::vector<Prepared>> step_problems = problems_of(current, step_requests);
    for (std::size_t ui = 0; ui < ties_.units.size(); ++ui) {
      const Unit& u = ties_.units[ui];
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
          if (!search.count_evaluation()) return false;
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
      const Nearest nr = nearest(pass, u.dims(), u.dir, out_.size, search.max_move, std::max(search.tol, 1e-3 * out_.size),
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
      const Unit& u = ties_.units[pu];
      const Vec2 x0 = u.slide ? z[offset_[pu]] * u.dir : Vec2(z[offset_[pu]], z[offset_[pu] + 1]);
      set_unit(z, pu, x0 + x);
      for (std::size_t ui = 0; ui < ties_.units.size(); ++ui)
        for (int k : u.points)
          if (std::binary_search(watch[ui].begin(), watch[ui].end(), k)) cached[ui].reset();
    }
    feasible = search.holds(delta_of(z));
  }
  return feasible;
}

/// Stage 2b: a compass search on the total squared displacement of a z that
/// holds; each trial is pulled back towards no move by bisection while it
/// still passes.
void FixRun::polish(std::vector<double>& z) {
  Search& search = *search_;
  const FixRequest& request = request_;
  auto ok = [&](const std::vector<double>& v) { return search.holds(delta_of(v)); };
  const double stop = std::max(search.tol, 1e-3 * out_.size);
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
  for (std::size_t ui = 0; ui < ties_.units.size(); ++ui)
    for (std::size_t i = offset_[ui]; i < offset_[ui + 1]; ++i)
      for (std::size_t c = offset_[ui]; c < offset_[ui + 1]; ++c) moved_coordinate[i] = moved_coordinate[i] || z[c] != 0;
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

FixResult FixRun::run() {
  if (judged_to_hold(spline_, a0_)) {
    out_.already = true;
    out_.spline = spline_;
    certify(out_);
    return std::move(out_);
  }
  out_.failing_segments = failing_segments(spline_, a0_, request_.requirement);
  if (request_.judge) {  // the caller's judge says whether, not where: every judged segment
    out_.failing_segments.clear();
    for (int i = a0_.range.first; i <= a0_.range.last; ++i) out_.failing_segments.push_back(i);
  }
  for (int i : out_.failing_segments)
    for (int k : segment_points(spline_, spline_.segments()[i])) acting_.insert(k);
  const std::vector<int> allowed = allowed_points();
  // Units of every allowed point: those acting on a failing segment are
  // tried alone; the others join the several-unit search (a segment that
  // fails only by its direction may need its neighbours moved).
  std::set<int> all_points;
  for (int k = 0; k < m_; ++k) all_points.insert(k);
  ties_ = build_units(spline_, a0_, allowed, request_.keep, all_points);
  out_.tie_joints = ties_.joints;
  out_.spline = spline_;
  if (std::none_of(ties_.units.begin(), ties_.units.end(), [&](const Unit& u) { return unit_acts(u); })) {
    out_.reason = "no point may move: every point acting on a failing segment is fixed or held by a tie";
    out_.nothing_moves = true;
    certify(out_);
    return std::move(out_);
  }

  Search& search = search_.emplace(spline_, request_, a0_);
  search.handles = ties_.handles;
  search.size = out_.size;
  search.tol = request_.tolerance * out_.size;
  search.max_move = request_.max_move > 0 ? request_.max_move : out_.size;
  search.deadline =
      start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(request_.max_seconds));
  if (request_.thread_cpu_clock && request_.max_seconds > 0) search.cpu_deadline = ThreadCpuDeadline(request_.max_seconds);

  each_unit_alone();

  offset_.assign(ties_.units.size() + 1, 0);
  for (std::size_t ui = 0; ui < ties_.units.size(); ++ui) offset_[ui + 1] = offset_[ui] + ties_.units[ui].dims();
  std::vector<double> z(offset_.back(), 0.0);
  bool feasible = false;
  if (best_unit_) {
    set_unit(z, *best_unit_, alone_[*best_unit_].x);
    feasible = true;
  }
  if (!feasible) feasible = greedy(z);
  if (feasible && (request_.together || !best_unit_)) polish(z);
  if (!feasible) {
    const bool counted_out = request_.max_evaluations > 0 && search.evaluations >= request_.max_evaluations;
    out_.reason = counted_out ? "no certified fix found in " + std::to_string(request_.max_evaluations) + " evaluations"
                  : search.timed_out
                      ? "no certified fix found in the time limit (" + format_number(request_.max_seconds) + " s)"
                      : "no certified fix within " + field("max_move") + " " + format_number(unit_ * search.max_move) +
                            " (" +
                            std::to_string(ties_.units.size()) + " unit(s) of motion tried)";
    out_.evaluations = search.evaluations;
    certify(out_);
    return std::move(out_);
  }
  const std::vector<Vec2> delta = delta_of(z);
  out_.spline = search.moved(delta);
  for (int k = 0; k < m_; ++k) {
    if (delta[k] == Vec2(0.0)) continue;
    PointMove pm{k, spline_.points()[k], out_.spline->points()[k], norm(out_.spline->points()[k] - spline_.points()[k])};
    out_.total_squared += pm.distance * pm.distance;
    out_.max_distance = std::max(out_.max_distance, pm.distance);
    out_.moves.push_back(pm);
  }
  out_.evaluations = search.evaluations;
  certify(out_);
  return std::move(out_);
}

}  // namespace

namespace {

// A curve whose size is outside fix_scale_exponent's range is searched as
// its copy scaled by 2^-e: multiplying by a power of two is exact there, so
// the copy has the same verdicts, regions and certified facts, and every
// length of the answer is the copy's times 2^e (the joints' curvatures times
// 2^-e). Without it norm() of a far-off curve's offsets overflowed, and
// every candidate lay beyond max_move.
BSpline scaled_spline(const BSpline& spline, int e) {
  std::vector<Vec2> pts(spline.points().begin(), spline.points().begin() + spline.unique_point_count());
  for (Vec2& p : pts) p *= std::ldexp(1.0, e);
  return spline.with_points(pts);
}

void scale_joint(Joint& j, int e) {
  j.kappa_left = std::ldexp(j.kappa_left, -e);
  j.kappa_right = std::ldexp(j.kappa_right, -e);
}

}  // namespace

int fix_scale_exponent(double size) {
  constexpr int kRange = 128;
  if (!(size > 0) || !std::isfinite(size)) return 0;
  const int e = std::ilogb(size);
  return std::abs(e) <= kRange ? 0 : e;
}

FixResult fix(const BSpline& spline, const FixRequest& request) {
  const auto start = Clock::now();
  const int e = fix_scale_exponent(curve_size(spline));
  if (e == 0) return FixRun(spline, request, start).run();
  check_fix_request(spline, request);  // its messages in the caller's units
  FixRequest r = request;
  r.max_move = std::ldexp(request.max_move, -e);
  if (request.judge) r.judge = [judge = request.judge, e](const BSpline& s) { return judge(scaled_spline(s, e)); };
  FixResult out = FixRun(scaled_spline(spline, -e), r, start, std::ldexp(1.0, e)).run();
  const auto up = [e](double v) { return std::ldexp(v, e); };
  if (out.spline) out.spline = scaled_spline(*out.spline, e);
  for (PointMove& m : out.moves) m.from = up(1) * m.from, m.to = up(1) * m.to, m.distance = up(m.distance);
  for (UnitFix& u : out.units) u.displacement = up(1) * u.displacement, u.distance = up(u.distance);
  out.total_squared = std::ldexp(out.total_squared, 2 * e);
  out.max_distance = up(out.max_distance);
  out.size = up(out.size);
  for (Joint& j : out.certificate.joints) scale_joint(j, e);
  if (out.certificate.seam) scale_joint(*out.certificate.seam, e);
  return out;
}

}  // namespace cmr
