#include "design/space_fix.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include <glm/geometric.hpp>

#include "spline/errors.hpp"
#include "spline/fields.hpp"

namespace cmr {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();

struct TimeUp {};

bool monotone(Curvature c) {
  return c == Curvature::increasing || c == Curvature::decreasing || c == Curvature::constant;
}

std::string fmt(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

std::string list(const std::vector<int>& v, const std::string& prefix = {}) {
  std::string out;
  for (int i : v) {
    if (!out.empty()) out += ", ";
    out += prefix;
    out += std::to_string(i);
  }
  return out;
}

/// Gram-Schmidt in doubles: orthonormal directions of the same plane.
SpacePlane orthonormal(SpacePlane p) {
  const Vec3 u = p.u / glm::length(p.u);
  Vec3 v = p.v - glm::dot(p.v, u) * u;
  const double lv = glm::length(v);
  if (!(lv > 0) || !std::isfinite(lv))
    throw InputFieldError(field("plane") + ": U and V are parallel (the plane is degenerate)");
  p.u = u;
  p.v = v / lv;
  return p;
}

/// One candidate's search state.
struct Search {
  const SpaceSpline& spline;
  const SpaceFixRequest& request;
  const std::vector<int>& ties_g1;
  const std::vector<int>& ties_g2;
  Clock::time_point deadline;
  long& evaluations;

  SpaceAnalyzeOptions options() const {
    SpaceAnalyzeOptions o;
    o.max_depth = request.max_depth;
    return o;
  }

  bool ties_hold(const SpaceAnalysis& a) const {
    const auto joint = [&](int index) -> const SpaceJoint* {
      if (a.seam && a.seam->index == index) return &*a.seam;
      for (const SpaceJoint& j : a.joints)
        if (j.index == index) return &j;
      return nullptr;
    };
    for (int i : ties_g1)
      if (const SpaceJoint* j = joint(i); !j || !j->g1) return false;
    for (int i : ties_g2)
      if (const SpaceJoint* j = joint(i); !j || !j->g2) return false;
    return true;
  }

  bool full_check(const SpaceSpline& moved, SpaceAnalysis* out = nullptr) const {
    SpaceAnalysis a = analyze_space(moved, options());
    const bool ok = space_fix_passes(a, request.no_zero_curvature) && ties_hold(a);
    if (out) *out = std::move(a);
    return ok;
  }
};

}  // namespace

bool space_fix_passes(const SpaceAnalysis& a, bool no_zero_curvature) {
  const bool mono = a.curvature == Direction::increasing || a.curvature == Direction::decreasing;
  return mono && (!no_zero_curvature || (!a.zero_curvature && !a.cusp));
}

namespace {

/// The spline with its distinct points replaced by `pts` (knots, weights and
/// name kept).
SpaceSpline with_points(const SpaceSpline& spline, const std::vector<Vec3>& pts) {
  std::vector<double> w;
  if (spline.is_rational()) w.assign(spline.weights().begin(), spline.weights().begin() + static_cast<long>(pts.size()));
  if (spline.closed()) return SpaceSpline::make_closed(spline.degree(), spline.period_knots(), pts, spline.name(), w);
  return SpaceSpline::make(spline.degree(), spline.knots(), pts, spline.name(), w);
}

/// The spline's distinct points.
std::vector<Vec3> unique_points(const SpaceSpline& spline) {
  const int m = spline.closed() ? spline.unique_point_count() : spline.point_count();
  return {spline.points().begin(), spline.points().begin() + m};
}

}  // namespace

SpaceSpline with_point_moved(const SpaceSpline& spline, int k, const Vec3& q) {
  std::vector<Vec3> pts = unique_points(spline);
  pts[static_cast<std::size_t>(k)] = q;
  return with_points(spline, pts);
}

namespace {

/// The request's numbers, checked before any work (InputFieldError naming the field).
void check_space_fix_request(const SpaceFixRequest& request) {
  if (request.max_depth < 0 || request.max_depth > kMaxDepth)
    throw InputFieldError(field("max_depth") + " " + std::to_string(request.max_depth) + " is outside 0.." +
                          std::to_string(kMaxDepth));
  if (!(request.max_move >= 0) || !std::isfinite(request.max_move))
    throw InputFieldError(field("max_move") + ": " + fmt(request.max_move) + " is not a distance >= 0");
  if (!(request.tolerance > 0) || !std::isfinite(request.tolerance) || request.tolerance >= 1)
    throw InputFieldError(field("tolerance") + ": " + fmt(request.tolerance) + " is not in (0, 1)");
}

/// Ties: joints not C1 (C2) by their knots that are G1 (G2) now stay so.
/// Fills ties_g1 and ties_g2; returns every tied joint, sorted.
std::vector<int> space_ties(const SpaceAnalysis& input, Keep keep, std::vector<int>& ties_g1, std::vector<int>& ties_g2) {
  std::vector<SpaceJoint> all = input.joints;
  if (input.seam) all.push_back(*input.seam);
  for (const SpaceJoint& j : all) {
    if (keep != Keep::none && j.continuity < 1 && j.g1) ties_g1.push_back(j.index);
    if (keep == Keep::g2 && j.continuity < 2 && j.g2) ties_g2.push_back(j.index);
  }
  std::vector<int> tied = ties_g1;
  for (int i : ties_g2)
    if (std::find(tied.begin(), tied.end(), i) == tied.end()) tied.push_back(i);
  std::sort(tied.begin(), tied.end());
  return tied;
}

/// The points tried: the request's (each must act on an involved segment),
/// else every point acting on one but an open curve's two ends.
std::vector<int> space_fix_candidates(const SpaceSpline& spline, const SpaceFixRequest& request,
                                      const std::vector<int>& involved, const std::string& failing_text) {
  const int m = spline.unique_point_count(), d = spline.degree();
  const auto acts = [&](int k) {
    const int twin = spline.twin(k);
    for (int s : involved) {
      const int first = spline.segments()[static_cast<std::size_t>(s)].span - d + 1;
      for (int i = first; i <= first + d; ++i)
        if (i == k || i == twin) return true;
    }
    return false;
  };
  std::vector<int> candidates;
  if (!request.points.empty()) {
    for (int k : request.points) {
      if (k < 0 || k >= m)
        throw InputFieldError(field("points") + ": P" + std::to_string(k) + " is outside P0..P" +
                              std::to_string(m - 1));
      if (std::find(request.held.begin(), request.held.end(), k) != request.held.end())
        throw InputFieldError(field("points") + ": P" + std::to_string(k) + " is held (it carries an end's jet)");
      if (!acts(k))
        throw InputFieldError(field("points") + ": P" + std::to_string(k) + " does not act on a failing segment (" +
                              failing_text + ")");
      if (std::find(candidates.begin(), candidates.end(), k) == candidates.end()) candidates.push_back(k);
    }
  } else {
    for (int k = 0; k < m; ++k)
      if ((spline.closed() || (k != 0 && k != m - 1)) && acts(k) &&
          std::find(request.held.begin(), request.held.end(), k) == request.held.end())
        candidates.push_back(k);
  }
  return candidates;
}

/// The nearest passing position found for one point, in its plane's
/// coordinates (a, b) = r (cos theta, sin theta); r = kInf: none.
struct RayHit {
  double r = kInf, theta = 0;
};

/// A handle of a G1 joint slides on its tangent line (1-D): the first
/// passing distance each way (2048 samples out to `limit`, never reaching
/// the node `to_node` away), then bisection to `tol`.
template <class Pass>
RayHit nearest_on_tangent(const Pass& pass, double limit, double to_node, double tol) {
  RayHit hit;
  for (const int sgn : {1, -1}) {
    const double lim = sgn > 0 ? limit : std::min(limit, to_node * (1 - 1e-9));
    constexpr int steps1 = 2048;
    const double st = lim / steps1;
    for (int j = 1; j <= steps1; ++j) {
      double hi_r = j * st, lo_r = (j - 1) * st;
      if (hi_r >= hit.r) break;
      if (!pass(sgn * hi_r, 0)) continue;
      while (hi_r - lo_r > tol) {
        const double mid = 0.5 * (lo_r + hi_r);
        (pass(sgn * mid, 0) ? hi_r : lo_r) = mid;
      }
      if (hi_r < hit.r) hit = {hi_r, sgn > 0 ? 0 : std::numbers::pi};
      break;
    }
  }
  return hit;
}

/// A free point (2-D, in its plane): a 32x32 grid of cells around it,
/// doubled out to `limit` until one passes; a finer grid inside the nearest
/// passing radius; then golden-section searches over the angle of the
/// nearest cells' rays, each ray scanned outwards and bisected to `tol`.
/// nullopt: no cell within `limit` passes.
template <class Pass>
std::optional<RayHit> nearest_in_plane(const Pass& pass, double size, double limit, double tol) {
  struct Cell {
    double a, b, r;
  };
  std::vector<Cell> passing;
  constexpr int n = 32;
  double R = std::min(size / 16, limit), cell_coarse = 0;
  for (;;) {
    cell_coarse = 2 * R / n;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double a = -R + (i + 0.5) * cell_coarse, b = -R + (j + 0.5) * cell_coarse, rad = std::hypot(a, b);
        if (rad <= limit && pass(a, b)) passing.push_back({a, b, rad});
      }
    if (!passing.empty() || R >= limit) break;
    R = std::min(2 * R, limit);
  }
  if (passing.empty()) return std::nullopt;
  const double r0 =
      std::min_element(passing.begin(), passing.end(), [](const Cell& x, const Cell& y) { return x.r < y.r; })->r;
  const double cell_fine = 2 * r0 / n;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double a = -r0 + (i + 0.5) * cell_fine, b = -r0 + (j + 0.5) * cell_fine, rad = std::hypot(a, b);
      if (rad <= r0 && pass(a, b)) passing.push_back({a, b, rad});
    }
  std::sort(passing.begin(), passing.end(), [](const Cell& x, const Cell& y) { return x.r < y.r; });
  const double rb = passing.front().r, diag = cell_fine * std::numbers::sqrt2;
  const double rmax = std::min(limit, rb + 4 * std::max(cell_coarse, cell_fine) * std::numbers::sqrt2);
  constexpr int steps = 96;
  const double step = rmax / steps;
  // A ray's first passing distance: a scan outwards, then bisection.
  const auto ray = [&](double theta) {
    const double c = std::cos(theta), s = std::sin(theta);
    for (int j = 1; j <= steps; ++j) {
      double hi_r = j * step;
      if (!pass(hi_r * c, hi_r * s)) continue;
      double lo_r = (j - 1) * step;
      while (hi_r - lo_r > tol) {
        const double mid = 0.5 * (lo_r + hi_r);
        (pass(mid * c, mid * s) ? hi_r : lo_r) = mid;
      }
      return hi_r;
    }
    return kInf;
  };
  RayHit hit{kInf, std::atan2(passing.front().b, passing.front().a)};
  int seeds = 0;
  for (const Cell& seed : passing) {
    if (seed.r > rb + 2 * diag || seeds == 6) break;
    ++seeds;
    const double t0s = std::atan2(seed.b, seed.a);
    const double delta = std::min(std::numbers::pi, 2 * diag / std::max(seed.r, tol));
    double x0 = t0s - delta, x3 = t0s + delta;
    constexpr double g = 0.6180339887498949;
    double x1 = x3 - g * (x3 - x0), x2 = x0 + g * (x3 - x0);
    double f1 = ray(x1), f2 = ray(x2);
    const double fs = ray(t0s);
    if (fs < hit.r) hit = {fs, t0s};
    for (int it = 0; it < 16; ++it) {
      if (f1 <= f2) {
        x3 = x2, x2 = x1, f2 = f1;
        x1 = x3 - g * (x3 - x0);
        f1 = ray(x1);
      } else {
        x0 = x1, x1 = x2, f1 = f2;
        x2 = x0 + g * (x3 - x0);
        f2 = ray(x2);
      }
    }
    if (f1 < hit.r) hit = {f1, x1};
    if (f2 < hit.r) hit = {f2, x2};
  }
  if (!(hit.r < kInf)) hit = {rb, std::atan2(passing.front().b, passing.front().a)};
  return hit;
}

/// Certify: the moved point rounded to doubles, analyze_space on the spline
/// so moved (Search::full_check); pushed outwards along the ray, by tol
/// doubling up to 12 times, where rounding lands just outside. The
/// certified radius, or nullopt.
std::optional<double> certified_radius(const Search& search, int k, const SpacePlane& plane, RayHit hit, double limit,
                                       double tol) {
  const Vec3 P = search.spline.points()[static_cast<std::size_t>(k)];
  for (int i = 0; i <= 12; ++i) {
    const double rad = hit.r + (i == 0 ? 0 : tol * std::ldexp(1.0, i - 1));
    const double a = rad * std::cos(hit.theta), b = rad * std::sin(hit.theta);
    const Vec3 q = P + a * plane.u + b * plane.v;
    if (!(glm::length(q - P) <= limit)) break;
    ++search.evaluations;
    if (search.full_check(with_point_moved(search.spline, k, q))) return rad;
  }
  return std::nullopt;
}

/// The answer: the best point moved, certified again (analyze_space and the ties).
void apply_best(SpaceFixResult& r, const SpaceSpline& spline, int point, const SpacePlane& plane, double a, double b,
                const Search& search) {
  const Vec3 P = spline.points()[static_cast<std::size_t>(point)];
  const Vec3 q = P + a * plane.u + b * plane.v;
  r.spline = with_point_moved(spline, point, q);
  r.certificate = analyze_space(*r.spline, search.options());
  r.certificate_holds = space_fix_passes(r.certificate, search.request.no_zero_curvature);
  r.ties_hold = search.ties_hold(r.certificate);
  r.fixed = r.certificate_holds && r.ties_hold;  // it was checked; a second look cannot differ
  r.moves.push_back({point, P, q, glm::length(q - P), plane});
  r.max_distance = r.moves.front().distance;
  r.total_squared = r.max_distance * r.max_distance;
}

/// No fix: no move, and the reason with what each point tried.
void explain_no_fix(SpaceFixResult& r, const std::string& max_move, const std::string& failing_text,
                    bool no_candidates, bool some_held) {
  r.moves.clear();
  r.spline.reset();
  std::string tried;
  for (const SpaceUnitFix& u : r.units) {
    if (!tried.empty()) tried += "; ";
    tried += "P";
    tried += std::to_string(u.point);
    tried += ": ";
    tried += u.reason;
  }
  r.reason = "no certified fix within " + field("max_move") + " " + max_move + " (" + failing_text +
             (no_candidates ? (some_held ? "; no point that may move acts on it (the others are held)" : "; no point acts on it")
                            : "; no single point moving in its plane makes |kappa| monotone: " + tried) +
             ")";
}

/// keep g1: the node of a tied joint (knot multiplicity >= degree: the curve
/// passes through it) does not move, and each of its handles only slides
/// along the line through the node (the tangent direction is kept exactly).
struct TiedNodes {
  enum class Role { free, slides, held };
  const SpaceSpline& spline;
  std::vector<int> nodes;

  TiedNodes(const SpaceSpline& s, const std::vector<int>& ties_g1) : spline(s) {
    const int N = s.segment_count(), d = s.degree();
    for (int j : ties_g1) nodes.push_back(wrap(s.segments()[static_cast<std::size_t>(j % N)].span - d + 1));
  }
  int wrap(int i) const {
    const int m = spline.unique_point_count();
    return spline.closed() ? ((i % m) + m) % m : i;
  }
  /// Point k: a tied node or a handle of two (held), the handle of one
  /// (slides; `node` set to that node), or free.
  Role role(int k, int& node) const {
    int handle_of = 0;
    bool is_node = false;
    for (int t : nodes) {
      if (t == k) is_node = true;
      if (wrap(t - 1) == k || wrap(t + 1) == k) ++handle_of, node = t;
    }
    if (is_node || handle_of > 1) return Role::held;
    return handle_of == 1 ? Role::slides : Role::free;
  }
  std::string held_reason(int k) const {
    const bool is_node = std::find(nodes.begin(), nodes.end(), k) != nodes.end();
    return is_node ? "the node of a G1 joint does not move with " + field("keep") + " g1 (" + field("keep") +
                         " none moves it)"
                   : "a handle of two G1 joints does not move with " + field("keep") + " g1 (" + field("keep") +
                         " none moves it)";
  }
};

/// The plane a point moves in: for a sliding handle, its tangent line (u,
/// away from the node) and any normal; else the request's plane, or the
/// default one. nullopt with `reason` set when the point cannot move; a bad
/// plane the caller gave throws.
std::optional<SpacePlane> unit_plane(const SpaceSpline& spline, const SpaceFixRequest& request, int k, int node,
                                     bool slide, std::string& reason) {
  const Vec3 P = spline.points()[static_cast<std::size_t>(k)];
  if (slide) {
    const Vec3 leg = P - spline.points()[static_cast<std::size_t>(node)];
    if (!(glm::length(leg) > 0)) {
      reason = "a handle on its G1 node has no tangent line to slide on";
      return std::nullopt;
    }
    const Vec3 u = glm::normalize(leg);
    const Vec3 axis = std::abs(u.x) <= std::abs(u.y) && std::abs(u.x) <= std::abs(u.z) ? Vec3{1, 0, 0}
                      : std::abs(u.y) <= std::abs(u.z)                               ? Vec3{0, 1, 0}
                                                                                      : Vec3{0, 0, 1};
    return orthonormal({P, u, glm::cross(u, axis)});
  }
  try {
    SpacePlane plane =
        request.plane_text.empty() ? default_space_plane(spline, k) : parse_space_plane(request.plane_text, P);
    plane.origin = P;
    return orthonormal(plane);
  } catch (const InputError& e) {
    if (!request.plane_text.empty()) throw;  // a bad --plane is the caller's error
    reason = marked_text(e);                 // fields marked: the caller shows them
    return std::nullopt;
  }
}

// The nearest certified move found so far: its point, distance, plane and
// coordinates in that plane.
struct BestMove {
  int point = -1;
  double distance = kInf;
  SpacePlane plane;
  double a = 0, b = 0;
};

// The nearest certified move of one candidate point, kept in best when it
// is nearer than the best so far; the point's entry (found, or why not) goes
// into r.units. Returns false when the search's time is up.
bool search_unit(int k, const Search& search, const TiedNodes& tied, double size, double max_move, double tol,
                 BestMove& best, SpaceFixResult& r) {
  const SpaceSpline& spline = search.spline;
  const SpaceFixRequest& request = search.request;
  const std::vector<int>& ties_g1 = search.ties_g1;
  const std::vector<int>& ties_g2 = search.ties_g2;
  long& evaluations = search.evaluations;
  SpaceUnitFix unit;
  unit.point = k;
  if (Clock::now() > search.deadline) {  // each candidate's region problem judges every segment once
    unit.reason = "search time limit (" + fmt(request.time_limit) + " s) reached";
    r.units.push_back(unit);
    return false;
  }
  const Vec3 P = spline.points()[static_cast<std::size_t>(k)];
  int node = -1;
  const TiedNodes::Role role = tied.role(k, node);
  if (role == TiedNodes::Role::held) {
    unit.reason = tied.held_reason(k);
    r.units.push_back(unit);
    return true;
  }
  const bool slide = role == TiedNodes::Role::slides;
  const std::optional<SpacePlane> chosen = unit_plane(spline, request, k, node, slide, unit.reason);
  if (!chosen) {
    r.units.push_back(unit);
    return true;
  }
  const SpacePlane plane = *chosen;
  unit.plane = plane;
  SpaceRegionRequest rr;
  rr.point = k;
  rr.plane = plane;
  rr.max_depth = request.max_depth;
  rr.width = rr.height = 1;
  rr.view = View{-1, -1, 1, 1};
  const SpaceRegionProblem problem = SpaceRegionProblem::make(spline, rr);
  const bool full = request.no_zero_curvature || !ties_g1.empty() || !ties_g2.empty();
  const auto pass = [&](double a, double b) {
    ++evaluations;
    if ((evaluations & 63) == 0 && Clock::now() > search.deadline) throw TimeUp{};
    const Direction l = problem.classify(a, b).label;
    if (l != Direction::increasing && l != Direction::decreasing) return false;
    if (!full) return true;
    return search.full_check(with_point_moved(spline, k, P + a * plane.u + b * plane.v));
  };
  // The farthest this unit may go: the request's, or nearer than the best so far.
  const double limit = std::min(max_move, best.distance);
  try {
    RayHit hit;
    if (slide) {
      hit = nearest_on_tangent(pass, limit, glm::length(P - spline.points()[static_cast<std::size_t>(node)]), tol);
      if (!(hit.r < kInf)) {
        unit.reason =
            "no certified position within " + fmt(limit) + " on its tangent line (" + field("keep") + " g1)";
        r.units.push_back(unit);
        return true;
      }
    } else {
      const std::optional<RayHit> found = nearest_in_plane(pass, size, limit, tol);
      if (!found) {
        unit.reason = limit < max_move ? "no fix nearer than the best so far (" + fmt(limit) + ")"
                                       : "no certified position within " + fmt(limit) + " in its plane";
        r.units.push_back(unit);
        return true;
      }
      hit = *found;
    }
    const double br = hit.r, bt = hit.theta;
    // Certify: the moved point rounded to doubles, analyze_space on the
    // spline so moved; pushed outwards along the ray where rounding lands
    // just outside.
    const std::optional<double> certified = certified_radius(search, k, plane, hit, limit, tol);
    if (!certified) {
      unit.reason = "the nearest position found (" + fmt(br) + ") is not certified by analyze";
      r.units.push_back(unit);
      return true;
    }
    const double rr_ok = *certified;
    const Vec3 q = P + rr_ok * std::cos(bt) * plane.u + rr_ok * std::sin(bt) * plane.v;
    unit.found = true;
    unit.displacement = q - P;
    unit.distance = glm::length(q - P);
    if (unit.distance < best.distance) best = {k, unit.distance, plane, rr_ok * std::cos(bt), rr_ok * std::sin(bt)};
  } catch (const TimeUp&) {
    unit.reason = "search time limit (" + fmt(request.time_limit) + " s) reached";
    r.units.push_back(unit);
    return false;
  }
  r.units.push_back(unit);
  return true;
}

}  // namespace

namespace {

/// space_fix on a curve of moderate size; `unit`: the caller's length of one
/// of the spline's units (the message's max_move is in the caller's units).
SpaceFixResult space_fix_at(const SpaceSpline& spline, const SpaceFixRequest& request, double unit) {
  const auto t0 = Clock::now();
  check_space_fix_request(request);
  SpaceFixResult r;
  const int N = spline.segment_count();
  Vec3 lo = spline.points().front(), hi = lo;
  for (const Vec3& p : spline.points()) lo = glm::min(lo, p), hi = glm::max(hi, p);
  r.size = glm::length(hi - lo);
  if (!(r.size > 0)) r.size = 1;
  const double max_move = request.max_move > 0 ? request.max_move : r.size;
  const double tol = request.tolerance * r.size;

  SpaceAnalyzeOptions o;
  o.max_depth = request.max_depth;
  const SpaceAnalysis input = analyze_space(spline, o);
  for (int i = 0; i < N; ++i) {
    const SpaceSegmentResult& s = input.segments[static_cast<std::size_t>(i)];
    const bool zero = request.no_zero_curvature && (s.cusp || (!s.straight && !s.zero_curvature.empty()));
    if (!monotone(s.curvature.curvature) || zero) r.failing_segments.push_back(i);
  }
  r.joint_conflicts = input.joint_conflicts;
  std::vector<int> ties_g1, ties_g2;
  r.tie_joints = space_ties(input, request.keep, ties_g1, ties_g2);

  long evaluations = 0;
  Search search{spline, request, ties_g1, ties_g2, t0 + std::chrono::duration_cast<Clock::duration>(
                                                          std::chrono::duration<double>(request.time_limit)),
                evaluations};

  if (space_fix_passes(input, request.no_zero_curvature)) {
    r.already = r.fixed = true;
    r.spline = spline;
    r.certificate = input;
    r.certificate_holds = true;
    r.ties_hold = true;
    r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return r;
  }

  // The segments a move must change: the failing ones, else those next to a
  // joint in conflict, else all (segments of both directions).
  std::vector<int> involved = r.failing_segments;
  if (involved.empty())
    for (int j : r.joint_conflicts) involved.push_back(j - 1), involved.push_back(j % N);
  if (involved.empty())
    for (int i = 0; i < N; ++i) involved.push_back(i);
  const std::string failing_text =
      !r.failing_segments.empty() ? "failing segments: " + list(r.failing_segments)
      : !r.joint_conflicts.empty() ? "joints in conflict: " + list(r.joint_conflicts)
                                   : "segments of both directions";
  const std::vector<int> candidates = space_fix_candidates(spline, request, involved, failing_text);

  const TiedNodes tied(spline, ties_g1);

  BestMove best;
  for (int k : candidates)
    if (!search_unit(k, search, tied, r.size, max_move, tol, best, r)) break;
  r.evaluations = evaluations;
  if (best.point >= 0) apply_best(r, spline, best.point, best.plane, best.a, best.b, search);
  if (!r.fixed) explain_no_fix(r, fmt(unit * max_move), failing_text, candidates.empty(), !request.held.empty());
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

// As fix() (design/fix.cpp) for planar curves: a curve whose size is outside
// fix_scale_exponent's range is searched as its copy scaled by 2^-e (exact)
// and every length of the answer scaled back by 2^e (curvatures and
// torsions by 2^-e). Without it glm::length of a difference near 2^600 was
// infinite, and every default plane came out degenerate. A --plane's
// directions are scale-free and its origin is not used.
SpaceSpline scaled_space_spline(const SpaceSpline& spline, int e) {
  std::vector<Vec3> pts = unique_points(spline);
  for (Vec3& p : pts) p *= std::ldexp(1.0, e);
  return with_points(spline, pts);
}

void scale_space_joint(SpaceJoint& j, int e) {
  for (double* v : {&j.kappa_left, &j.kappa_right, &j.tau_left, &j.tau_right}) *v = std::ldexp(*v, -e);
}

}  // namespace

SpaceFixResult space_fix(const SpaceSpline& spline, const SpaceFixRequest& request) {
  Vec3 lo = spline.points().front(), hi = lo;
  for (const Vec3& p : spline.points()) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double size = std::hypot(hi.x - lo.x, hi.y - lo.y, hi.z - lo.z);
  const int e = fix_scale_exponent(size);
  if (e == 0) return space_fix_at(spline, request, 1);
  check_space_fix_request(request);  // its messages in the caller's units
  SpaceFixRequest r = request;
  r.max_move = std::ldexp(request.max_move, -e);
  SpaceFixResult out = space_fix_at(scaled_space_spline(spline, -e), r, std::ldexp(1.0, e));
  const double up = std::ldexp(1.0, e);
  if (out.spline) out.spline = scaled_space_spline(*out.spline, e);
  for (SpacePointMove& m : out.moves)
    m.from *= up, m.to *= up, m.distance *= up, m.plane.origin *= up;
  for (SpaceUnitFix& u : out.units) {
    u.distance *= up;
    u.displacement *= up;
    if (u.plane) u.plane->origin *= up;
  }
  out.size *= up;
  out.max_distance *= up;
  out.total_squared = std::ldexp(out.total_squared, 2 * e);
  for (SpaceJoint& j : out.certificate.joints) scale_space_joint(j, e);
  if (out.certificate.seam) scale_space_joint(*out.certificate.seam, e);
  return out;
}

}  // namespace cmr
