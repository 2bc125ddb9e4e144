#include "design/space_fix.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
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

SpaceSpline with_point_moved(const SpaceSpline& spline, int k, const Vec3& q) {
  const int m = spline.unique_point_count();
  std::vector<Vec3> pts(spline.points().begin(), spline.points().begin() + (spline.closed() ? m : spline.point_count()));
  pts[static_cast<std::size_t>(k)] = q;
  std::vector<double> w;
  if (spline.is_rational()) w.assign(spline.weights().begin(), spline.weights().begin() + static_cast<long>(pts.size()));
  if (spline.closed()) return SpaceSpline::make_closed(spline.degree(), spline.period_knots(), pts, spline.name(), w);
  return SpaceSpline::make(spline.degree(), spline.knots(), pts, spline.name(), w);
}

SpaceFixResult space_fix(const SpaceSpline& spline, const SpaceFixRequest& request) {
  const auto t0 = Clock::now();
  if (request.max_depth < 0 || request.max_depth > kMaxDepth)
    throw InputFieldError(field("max_depth") + " " + std::to_string(request.max_depth) + " is outside 0.." +
                          std::to_string(kMaxDepth));
  if (!(request.max_move >= 0) || !std::isfinite(request.max_move))
    throw InputFieldError(field("max_move") + ": " + fmt(request.max_move) + " is not a distance >= 0");
  if (!(request.tolerance > 0) || !std::isfinite(request.tolerance) || request.tolerance >= 1)
    throw InputFieldError(field("tolerance") + ": " + fmt(request.tolerance) + " is not in (0, 1)");
  SpaceFixResult r;
  const int m = spline.unique_point_count(), N = spline.segment_count(), d = spline.degree();
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
  // Ties: joints not C1 (C2) by their knots that are G1 (G2) now stay so.
  std::vector<int> ties_g1, ties_g2;
  std::vector<SpaceJoint> all = input.joints;
  if (input.seam) all.push_back(*input.seam);
  for (const SpaceJoint& j : all) {
    if (request.keep != Keep::none && j.continuity < 1 && j.g1) ties_g1.push_back(j.index);
    if (request.keep == Keep::g2 && j.continuity < 2 && j.g2) ties_g2.push_back(j.index);
  }
  r.tie_joints = ties_g1;
  for (int i : ties_g2)
    if (std::find(r.tie_joints.begin(), r.tie_joints.end(), i) == r.tie_joints.end()) r.tie_joints.push_back(i);
  std::sort(r.tie_joints.begin(), r.tie_joints.end());

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
  const auto acts = [&](int k) {
    const int twin = spline.twin(k);
    for (int s : involved) {
      const int first = spline.segments()[static_cast<std::size_t>(s)].span - d + 1;
      for (int i = first; i <= first + d; ++i)
        if (i == k || i == twin) return true;
    }
    return false;
  };
  const std::string failing_text =
      !r.failing_segments.empty() ? "failing segments: " + list(r.failing_segments)
      : !r.joint_conflicts.empty() ? "joints in conflict: " + list(r.joint_conflicts)
                                   : "segments of both directions";
  std::vector<int> candidates;
  if (!request.points.empty()) {
    for (int k : request.points) {
      if (k < 0 || k >= m)
        throw InputFieldError(field("points") + ": P" + std::to_string(k) + " is outside P0..P" +
                              std::to_string(m - 1));
      if (!acts(k))
        throw InputFieldError(field("points") + ": P" + std::to_string(k) + " does not act on a failing segment (" +
                              failing_text + ")");
      if (std::find(candidates.begin(), candidates.end(), k) == candidates.end()) candidates.push_back(k);
    }
  } else {
    for (int k = 0; k < m; ++k)
      if ((spline.closed() || (k != 0 && k != m - 1)) && acts(k)) candidates.push_back(k);
  }

  // keep g1: the node of a tied joint (knot multiplicity >= degree: the curve
  // passes through it) does not move, and each of its handles only slides
  // along the line through the node (the tangent direction is kept exactly).
  const auto wrap = [&](int i) { return spline.closed() ? ((i % m) + m) % m : i; };
  std::vector<int> tied_nodes;
  for (int j : ties_g1) {
    const int seg = j % N;
    tied_nodes.push_back(wrap(spline.segments()[static_cast<std::size_t>(seg)].span - d + 1));
  }

  struct Best {
    int point = -1;
    double distance = kInf;
    SpacePlane plane;
    double a = 0, b = 0;
  } best;

  for (int k : candidates) {
    SpaceUnitFix unit;
    unit.point = k;
    if (Clock::now() > search.deadline) {  // each candidate's region problem judges every segment once
      unit.reason = "search time limit (" + fmt(request.time_limit) + " s) reached";
      r.units.push_back(unit);
      break;
    }
    const Vec3 P = spline.points()[static_cast<std::size_t>(k)];
    int handle_of = 0, node = -1;
    bool is_node = false;
    for (int t : tied_nodes) {
      if (t == k) is_node = true;
      if (wrap(t - 1) == k || wrap(t + 1) == k) ++handle_of, node = t;
    }
    if (is_node || handle_of > 1) {
      unit.reason = is_node ? "the node of a G1 joint does not move with " + field("keep") + " g1 (" + field("keep") +
                                  " none moves it)"
                            : "a handle of two G1 joints does not move with " + field("keep") + " g1 (" +
                                  field("keep") + " none moves it)";
      r.units.push_back(unit);
      continue;
    }
    const bool slide = handle_of == 1;
    SpacePlane plane;
    if (slide) {  // u: along the tangent line, away from the node; v: any normal
      const Vec3 leg = P - spline.points()[static_cast<std::size_t>(node)];
      if (!(glm::length(leg) > 0)) {
        unit.reason = "a handle on its G1 node has no tangent line to slide on";
        r.units.push_back(unit);
        continue;
      }
      const Vec3 u = glm::normalize(leg);
      const Vec3 axis = std::abs(u.x) <= std::abs(u.y) && std::abs(u.x) <= std::abs(u.z) ? Vec3{1, 0, 0}
                        : std::abs(u.y) <= std::abs(u.z)                               ? Vec3{0, 1, 0}
                                                                                        : Vec3{0, 0, 1};
      plane = orthonormal({P, u, glm::cross(u, axis)});
    } else try {
      plane = request.plane_text.empty() ? default_space_plane(spline, k) : parse_space_plane(request.plane_text, P);
      plane.origin = P;
      plane = orthonormal(plane);
    } catch (const InputError& e) {
      if (!request.plane_text.empty()) throw;  // a bad --plane is the caller's error
      unit.reason = marked_text(e);  // fields marked: the caller shows them
      r.units.push_back(unit);
      continue;
    }
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
      double br = kInf, bt = 0;
      if (slide) {  // 1-D: the first passing distance each way, never reaching the node
        const double to_node = glm::length(P - spline.points()[static_cast<std::size_t>(node)]);
        for (const int sgn : {1, -1}) {
          const double lim = sgn > 0 ? limit : std::min(limit, to_node * (1 - 1e-9));
          constexpr int steps1 = 2048;
          const double st = lim / steps1;
          for (int j = 1; j <= steps1; ++j) {
            double hi_r = j * st, lo_r = (j - 1) * st;
            if (hi_r >= br) break;
            if (!pass(sgn * hi_r, 0)) continue;
            while (hi_r - lo_r > tol) {
              const double mid = 0.5 * (lo_r + hi_r);
              (pass(sgn * mid, 0) ? hi_r : lo_r) = mid;
            }
            if (hi_r < br) br = hi_r, bt = sgn > 0 ? 0 : std::numbers::pi;
            break;
          }
        }
        if (!(br < kInf)) {
          unit.reason =
              "no certified position within " + fmt(limit) + " on its tangent line (" + field("keep") + " g1)";
          r.units.push_back(unit);
          continue;
        }
      } else {
      struct Cell {
        double a, b, r;
      };
      std::vector<Cell> passing;
      constexpr int n = 32;
      double R = std::min(r.size / 16, limit), cell_coarse = 0;
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
      if (passing.empty()) {
        unit.reason = limit < max_move ? "no fix nearer than the best so far (" + fmt(limit) + ")"
                                       : "no certified position within " + fmt(limit) + " in its plane";
        r.units.push_back(unit);
        continue;
      }
      const auto nearest = [&] {
        return std::min_element(passing.begin(), passing.end(), [](const Cell& x, const Cell& y) { return x.r < y.r; })
            ->r;
      };
      const double r0 = nearest();
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
      bt = std::atan2(passing.front().b, passing.front().a);
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
        if (fs < br) br = fs, bt = t0s;
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
        if (f1 < br) br = f1, bt = x1;
        if (f2 < br) br = f2, bt = x2;
      }
      if (!(br < kInf)) br = rb, bt = std::atan2(passing.front().b, passing.front().a);
      }
      // Certify: the moved point rounded to doubles, analyze_space on the
      // spline so moved; pushed outwards along the ray where rounding lands
      // just outside.
      bool ok = false;
      double rr_ok = br;
      for (int i = 0; i <= 12 && !ok; ++i) {
        const double rad = br + (i == 0 ? 0 : tol * std::ldexp(1.0, i - 1));
        const double a = rad * std::cos(bt), b = rad * std::sin(bt);
        const Vec3 q = P + a * plane.u + b * plane.v;
        if (!(glm::length(q - P) <= limit)) break;
        ++evaluations;
        if (search.full_check(with_point_moved(spline, k, q))) ok = true, rr_ok = rad;
      }
      if (!ok) {
        unit.reason = "the nearest position found (" + fmt(br) + ") is not certified by analyze";
        r.units.push_back(unit);
        continue;
      }
      const Vec3 q = P + rr_ok * std::cos(bt) * plane.u + rr_ok * std::sin(bt) * plane.v;
      unit.found = true;
      unit.displacement = q - P;
      unit.distance = glm::length(q - P);
      if (unit.distance < best.distance) best = {k, unit.distance, plane, rr_ok * std::cos(bt), rr_ok * std::sin(bt)};
    } catch (const TimeUp&) {
      unit.reason = "search time limit (" + fmt(request.time_limit) + " s) reached";
      r.units.push_back(unit);
      break;
    }
    r.units.push_back(unit);
  }
  r.evaluations = evaluations;
  if (best.point >= 0) {
    const Vec3 P = spline.points()[static_cast<std::size_t>(best.point)];
    const Vec3 q = P + best.a * best.plane.u + best.b * best.plane.v;
    r.spline = with_point_moved(spline, best.point, q);
    r.certificate = analyze_space(*r.spline, o);
    r.certificate_holds = space_fix_passes(r.certificate, request.no_zero_curvature);
    r.ties_hold = search.ties_hold(r.certificate);
    r.fixed = r.certificate_holds && r.ties_hold;  // it was checked; a second look cannot differ
    r.moves.push_back({best.point, P, q, glm::length(q - P), best.plane});
    r.max_distance = r.moves.front().distance;
    r.total_squared = r.max_distance * r.max_distance;
  }
  if (!r.fixed) {
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
    r.reason = "no certified fix within " + field("max_move") + " " + fmt(max_move) + " (" + failing_text +
               (candidates.empty() ? "; no point acts on it"
                                   : "; no single point moving in its plane makes |kappa| monotone: " + tried) +
               ")";
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

}  // namespace cmr
