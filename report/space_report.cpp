#include "report/space_report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

#include <glm/geometric.hpp>

#include "draw/draw.hpp"
#include "io/output.hpp"
#include "region/view_fit.hpp"
#include "report/g3.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"

namespace cmr::report {

namespace {

const char* sign_word(int s) { return s > 0 ? "positive" : (s < 0 ? "negative" : "changes-or-zero"); }

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

/// A direction of the default plane named by the control point it leads to
/// ("P4 − P3"), read off the plane default_space_plane returned.
std::string direction_name(const SpaceSpline& s, int k, Vec3 dir) {
  const Vec3 at = s.points()[static_cast<std::size_t>(k)];
  for (int i = 0; i < s.unique_point_count(); ++i)
    if (i != k && s.points()[static_cast<std::size_t>(i)] - at == dir)
      return "P" + std::to_string(i) + " − P" + std::to_string(k);
  return "(" + num(dir.x) + ", " + num(dir.y) + ", " + num(dir.z) + ")";
}

nlohmann::ordered_json vec3_json(Vec3 p) { return {p.x, p.y, p.z}; }

}  // namespace

std::string space_region_png(const SpaceSpline& spline, const SpacePlane& plane, const RegionResult& image, int point,
                             int max_depth, bool depth_shading) {
  const BSpline seen = project_to_plane(spline, plane);
  draw::RegionPicture pic;
  pic.spline = &seen;
  pic.layers = {&image};
  pic.points = {point};
  pic.max_depth = max_depth;
  pic.depth_shading = depth_shading;
  // The legend (drawn when the picture is large enough) ends with the plane
  // and its axes: which way a and b run in space.
  pic.legend = true;
  pic.note = space_plane_name(spline, plane, point);
  return draw::region_png(pic);
}

std::string space_plane_name(const SpaceSpline& spline, const SpacePlane& plane, int point) {
  std::string name = "plane through P";
  name.append(std::to_string(point))
      .append(": a (right) along ")
      .append(direction_name(spline, point, plane.u))
      .append(", b (up) along ")
      .append(direction_name(spline, point, plane.v));
  std::string ascii;  // for the picture's font: "P4 - P3"
  const std::string minus = "\u2212";
  for (std::size_t i = 0; i < name.size();)
    if (name.compare(i, minus.size(), minus) == 0) ascii.push_back('-'), i += minus.size();
    else ascii.push_back(name[i++]);
  return ascii;
}

SpaceViewFit fit_space_view(const SpaceSpline& spline, const SpaceRegionRequest& request) {
  SpaceRegionRequest base = request;
  base.view.reset();
  const SpaceRegionProblem polygon = SpaceRegionProblem::make(spline, base);
  const SpacePlane plane = *polygon.request().plane;
  const View v0 = *polygon.request().view;
  SpaceViewFit fit;
  fit.view = v0;
  constexpr int kProbe = 64;
  SpaceRegionRequest probe = base;
  probe.plane = plane;
  probe.width = probe.height = kProbe;
  probe.view = ViewFit::probe_view(v0);
  ViewFit box;
  fit.probe_pixels = box.add_region(SpaceRegionProblem::make(spline, probe).render(), *probe.view);
  if (box.empty()) {
    fit.empty = true;
    return fit;
  }
  // The moved point's plane coordinates (a, b): least squares on U, V (exact in the plane).
  const Vec3 q = spline.points()[static_cast<std::size_t>(request.point)] - plane.origin;
  const double uu = glm::dot(plane.u, plane.u), uv = glm::dot(plane.u, plane.v), vv = glm::dot(plane.v, plane.v);
  const double qu = glm::dot(q, plane.u), qv = glm::dot(q, plane.v), det = uu * vv - uv * uv;
  box.add_point((qu * vv - qv * uv) / det, (qv * uu - qu * uv) / det);
  fit.view = box.view(request.width, request.height);
  return fit;
}

SpaceThumbnail space_thumbnail(const SpaceSpline& spline, int k, int size, int max_depth, double time_limit) {
  SpaceThumbnail t;
  t.point = k;
  try {
    SpaceRegionRequest request;  // no plane: default_space_plane, as `cmr region --point K`
    request.point = k;
    request.width = request.height = size;
    request.max_depth = max_depth;
    request.time_limit = time_limit;
    request.view = fit_space_view(spline, request).view;  // the region and the point, as `cmr region` without --view
    const SpaceRegionProblem problem = SpaceRegionProblem::make(spline, request);
    t.plane = *problem.request().plane;
    t.image = problem.render();
    t.png = space_region_png(spline, t.plane, t.image, k, max_depth);
    t.plane_name = "the plane through P" + std::to_string(k) + " spanned by " + direction_name(spline, k, t.plane.u) +
                   " and " + direction_name(spline, k, t.plane.v);
  } catch (const InputError& e) {
    t.error = marked_text(e);  // fields marked: space_report shows them as its options say
  }
  return t;
}

nlohmann::ordered_json space_segment_json(const SpaceSpline& spline, const SpaceAnalysis& a, std::size_t i) {
  const Segment& s = spline.segments()[i];
  const SpaceSegmentResult& r = a.segments[i];
  nlohmann::ordered_json j = {{"index", s.index},
                              {"interval", {s.a, s.b}},
                              {"class", r.cusp ? "cusp" : (r.straight ? "straight" : "regular")},
                              {"curvature", to_string(r.curvature.curvature)},
                              {"zero_curvature", r.zero_curvature},
                              {"depth", r.curvature.depth},
                              {"exact", r.exact_used}};
  if (r.torsion) {
    j["torsion"] = to_string(r.torsion->curvature);
    j["torsion_depth"] = r.torsion->depth;
    j["torsion_sign"] = sign_word(r.torsion_sign);
    j["torsion_sign_changes"] = r.torsion_sign_changes;
    j["planar"] = r.planar;
  }
  return j;
}

nlohmann::ordered_json space_joint_json(const SpaceAnalysis& a, const SpaceJoint& j) {
  std::string continuity = std::to_string(j.continuity);
  continuity.insert(continuity.begin(), 'C');
  nlohmann::ordered_json json = {{"index", j.index},
                                 {"knot", j.knot},
                                 {"multiplicity", j.multiplicity},
                                 {"continuity", continuity},
                                 {"g1", j.g1},
                                 {"g2", j.g2},
                                 {"angle", j.angle_deg},
                                 {"normal_angle", j.normal_angle_deg},
                                 {"zero_tangent", j.zero_tangent},
                                 {"kappa_left", j.kappa_left},
                                 {"kappa_right", j.kappa_right},
                                 {"jump", j.jump > 0 ? "up" : (j.jump < 0 ? "down" : "none")},
                                 {"tau_left", j.tau_left},
                                 {"tau_right", j.tau_right},
                                 {"torsion_jump", j.torsion_jump > 0 ? "up" : (j.torsion_jump < 0 ? "down" : "none")}};
  if (a.seam && j.index == a.seam->index) json["seam"] = true;
  return json;
}

nlohmann::ordered_json space_verdict_json(const SpaceAnalysis& a) {
  nlohmann::ordered_json verdict = {{"dimension", 3},
                                    {"curvature", to_string(a.curvature)},
                                    {"zero_curvature", a.zero_curvature},
                                    {"cusp", a.cusp}};
  if (a.torsion) {
    verdict["torsion"] = to_string(*a.torsion);
    verdict["planar"] = a.planar;
  }
  if (!a.joint_conflicts.empty()) verdict["joint_conflicts"] = a.joint_conflicts;
  return verdict;
}

nlohmann::ordered_json space_analysis_json(const SpaceSpline& spline, const SpaceAnalysis& a) {
  nlohmann::ordered_json segs = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < a.segments.size(); ++i) segs.push_back(space_segment_json(spline, a, i));
  nlohmann::ordered_json joints = nlohmann::ordered_json::array();
  for (const SpaceJoint& j : a.joints) joints.push_back(space_joint_json(a, j));
  if (a.seam) joints.push_back(space_joint_json(a, *a.seam));
  return {{"segments", segs}, {"joints", joints}, {"spline", space_verdict_json(a)}};
}

namespace {

/// The violations of each gate (report/gates.hpp's rules, read in 3D: a
/// smooth joint is a G1 one without a zero tangent; zero curvature is the
/// inflection's analogue).
std::vector<GateResult> space_gates(const SpaceReport& r, const SpaceReportOptions& options) {
  std::vector<GateResult> out;
  const SpaceSpline& spline = *r.spline;
  const auto& segments = spline.segments();
  for (const Gate& gate : options.gates) {
    GateResult g{gate, {}};
    const auto at = [&](int i, double t, std::string message) {
      GateViolation v;
      v.segment = i;
      v.t = t;
      const Segment& s = segments[static_cast<std::size_t>(i)];
      v.local_t = s.b > s.a ? (t - s.a) / (s.b - s.a) : 0;
      v.message = std::move(message);
      g.violations.push_back(std::move(v));
    };
    switch (gate.kind) {
      case Gate::Kind::extrema_at_nodes:
      case Gate::Kind::max_extrema_per_segment:
        for (std::size_t i = 0; i < r.extrema.size(); ++i) {
          if (r.turning_deviation[i] <= options.constant_tolerance) continue;  // an arc of constant curvature
          const auto& ex = r.extrema[i];
          const int allowed = gate.kind == Gate::Kind::extrema_at_nodes ? 0 : gate.max_extrema;
          if (static_cast<int>(ex.size()) <= allowed) continue;
          if (gate.kind == Gate::Kind::extrema_at_nodes) {
            for (const SpaceExtremum& e : ex)
              at(static_cast<int>(i), e.t,
                 std::string("curvature ") + (e.maximum ? "maximum" : "minimum") + " inside segment " +
                     std::to_string(i) + " at t = " + num(e.t));
          } else {
            at(static_cast<int>(i), ex[static_cast<std::size_t>(allowed)].t,
               std::to_string(ex.size()) + " curvature extrema inside segment " + std::to_string(i) + " (at most " +
                   std::to_string(allowed) + "); the first extra at t = " + num(ex[static_cast<std::size_t>(allowed)].t));
          }
        }
        break;
      case Gate::Kind::g2_at_smooth_nodes: {
        std::vector<const SpaceJoint*> joints;
        for (const SpaceJoint& j : r.analysis.joints) joints.push_back(&j);
        if (r.analysis.seam) joints.push_back(&*r.analysis.seam);
        for (const SpaceJoint* j : joints) {
          if (!j->g1 || j->zero_tangent) continue;  // a corner: exempt
          const double kl = j->kappa_left, kr = j->kappa_right;
          if (!std::isfinite(kl) || !std::isfinite(kr)) continue;
          const double scale = std::max(kl, kr);
          if (std::abs(kl - kr) <= gate.tolerance * scale) continue;
          GateViolation v;
          v.joint = j->index;
          v.t = j->knot;
          v.message = "curvature " + num(kl) + " | " + num(kr) + " at smooth joint " + std::to_string(j->index) +
                      " (t = " + num(j->knot) + "): differs by " + num(100 * std::abs(kl - kr) / scale) + "%";
          g.violations.push_back(std::move(v));
        }
        break;
      }
      case Gate::Kind::g3_at_smooth_nodes:
        for (GateViolation& v : space_g3_violations(spline, r.analysis, gate.tolerance)) g.violations.push_back(std::move(v));
        break;
      case Gate::Kind::no_inflection:
        for (std::size_t i = 0; i < r.analysis.segments.size(); ++i)
          for (double t : r.analysis.segments[i].zero_curvature)
            at(static_cast<int>(i), t, "zero curvature (kappa = 0) in segment " + std::to_string(i) + " at t = " + num(t));
        break;
      case Gate::Kind::each_piece:
        for (std::size_t i = 0; i < r.analysis.segments.size(); ++i) {
          const Curvature d = r.analysis.segments[i].curvature.curvature;
          if (d == Curvature::increasing || d == Curvature::decreasing || d == Curvature::constant ||
              r.turning_deviation[i] <= options.constant_tolerance)
            continue;
          at(static_cast<int>(i), segments[i].a,
             "segment " + std::to_string(i) +
                 (d == Curvature::non_monotone ? " is not monotone on its own" : " is undecided at the depth limit"));
        }
        break;
      case Gate::Kind::unimodal_runs:
      case Gate::Kind::xy_extrema_at_nodes:
      case Gate::Kind::g1_between_masters:
      case Gate::Kind::curvature_between_masters:
      case Gate::Kind::extrema_between_masters:
        break;  // refused by space_requirements
    }
    out.push_back(std::move(g));
  }
  return out;
}

}  // namespace

void space_requirements(const ReportOptions& parsed, SpaceReportOptions& o, const std::string& file) {
  if (parsed.require) {
    if (parsed.require->split)
      throw InputFieldError(file + ": a space curve: " + field("require") + " " + to_string(*parsed.require) +
                            " has no meaning in 3D (|kappa| has no sign to split at a joint); use cmrwi or cmr");
    o.require_monotone = true;
    o.require_no_zero_curvature = parsed.require->mode == Mode::cmr;
  }
  for (const Gate& g : parsed.gates) {
    if (g.kind == Gate::Kind::unimodal_runs || g.kind == Gate::Kind::xy_extrema_at_nodes)
      throw InputFieldError(file + ": a space curve: " + field("require") + " " + to_string(g) +
                            " is a rule for font outlines, not for space curves");
    if (is_interpolation_gate(g))
      throw InputFieldError(file + ": a space curve: " + field("require") + " " + to_string(g) +
                            " judges a font's masters (a .designspace or a variable font), not a space curve");
    o.gates.push_back(g);
  }
}

std::vector<Finding> space_findings(const SpaceReport& r, const std::string& name, const SpaceReportOptions& options) {
  std::vector<Finding> out;
  if (!r.error.empty() || !r.spline) return out;
  const std::string glyph = r.spline->name();
  if (options.require_monotone && !r.check_pass) {
    Finding f;
    f.file = name;
    f.glyph = glyph;
    f.gate = options.require_no_zero_curvature ? "cmr" : "cmrwi";
    f.message = glyph + ": fails the " + f.gate + " check (curvature " + to_string(r.analysis.curvature) +
                (options.require_no_zero_curvature && r.analysis.zero_curvature ? ", zero curvature" : "") + ")";
    out.push_back(std::move(f));
  }
  for (const GateResult& g : r.gates)
    for (const GateViolation& v : g.violations) {
      Finding f;
      f.file = name;
      f.glyph = glyph;
      f.gate = to_string(g.gate);
      f.node = v.segment >= 0 ? "segment " + std::to_string(v.segment)
               : v.joint >= 0 ? "joint " + std::to_string(v.joint)
                              : std::string();
      f.message = glyph + ": " + v.message;
      out.push_back(std::move(f));
    }
  return out;
}

SpaceReport space_report_analysis(const std::string& file, const SpaceReportOptions& options) {
  SpaceReport r;
  r.file = file;
  try {
    r.spline = read_space_spline_file(file);
  } catch (const InputError& e) {
    r.error = options.show_fields(marked_text(e));
    return r;
  }
  SpaceAnalyzeOptions o;
  o.max_depth = options.max_depth;
  o.torsion = options.torsion;
  o.torsion_tolerance = options.torsion_tolerance;
  o.continuity = options.continuity;
  r.analysis = analyze_space(*r.spline, o);
  r.kappa_min = std::numeric_limits<double>::infinity();
  r.kappa_max = 0;
  double lo_all = std::numeric_limits<double>::infinity(), hi_all = 0, length_all = 0;
  r.near_constant = !r.analysis.cusp;
  for (const Segment& s : r.spline->segments()) {
    r.extrema.push_back(space_curvature_extrema(*r.spline, s));
    for (int i = 0; i <= 64; ++i) {
      const double k = space_curvature(*r.spline, s.a + (s.b - s.a) * i / 64.0);
      if (!std::isfinite(k)) continue;
      r.kappa_min = std::min(r.kappa_min, k);
      r.kappa_max = std::max(r.kappa_max, k);
    }
    // The planar report's spread (report.cpp, curvature_range): |kappa| at
    // the segment's ends and at its stationary points.
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    const auto consider = [&](double t) {
      const double k = space_curvature(*r.spline, t);
      if (!std::isfinite(k)) return;
      lo = std::min(lo, k), hi = std::max(hi, k);
    };
    consider(s.a);
    consider(s.b);
    for (const SpaceExtremum& e : r.extrema.back()) consider(e.t);
    const double spread = hi > 0 && std::isfinite(lo) ? (hi - lo) / hi : (hi > 0 ? 1.0 : 0.0);
    r.kappa_spread.push_back(spread);
    // The planar report's rule (report.hpp, turning_deviation).
    const double length = polygon_length(bezier_points(*r.spline, s));
    r.turning_deviation.push_back(!std::isfinite(lo) ? (hi > 0 ? std::numeric_limits<double>::infinity() : 0.0)
                                                     : turning_deviation(lo, hi, length));
    length_all += length;
    if (std::isfinite(lo)) lo_all = std::min(lo_all, lo), hi_all = std::max(hi_all, hi);
  }
  if (!std::isfinite(r.kappa_min)) r.kappa_min = 0;
  r.spread = hi_all > 0 && std::isfinite(lo_all) ? (hi_all - lo_all) / hi_all : 0;
  r.deviation = hi_all > 0 && std::isfinite(lo_all) ? turning_deviation(lo_all, hi_all, length_all) : 0;
  for (double x : r.turning_deviation) r.near_constant = r.near_constant && x <= options.constant_tolerance;
  r.near_constant = r.near_constant && r.deviation <= options.constant_tolerance && hi_all > 0;
  const bool monotone = r.analysis.curvature == Direction::increasing || r.analysis.curvature == Direction::decreasing;
  r.check_pass = (monotone || r.near_constant) && !(options.require_no_zero_curvature && r.analysis.zero_curvature);
  r.gates = space_gates(r, options);
  // As a planar report: the curvature check counts unless only gates are asked for.
  r.pass = options.require_monotone || r.gates.empty() ? r.check_pass : true;
  for (const GateResult& g : r.gates) r.pass = r.pass && g.pass();
  return r;
}

namespace {

/// "P3, P5-P9, P12": points, runs of three or more as ranges.
std::string point_ranges(const std::vector<int>& points) {
  std::string out;
  for (std::size_t i = 0; i < points.size();) {
    std::size_t j = i;
    while (j + 1 < points.size() && points[j + 1] == points[j] + 1) ++j;
    if (!out.empty()) out += ", ";
    out += "P" + std::to_string(points[i]);
    if (j >= i + 2) out += "-P" + std::to_string(points[j]), i = j + 1;
    else ++i;
  }
  return out;
}

/// Why a thumbnail or a fix search was left out (fields marked).
std::string budget_spent(const SpaceReportOptions& o) {
  return "the run's budget for fix searches and regions (" + field("fix_budget") + " " + num(o.budget) + " s) was spent";
}

bool needs_fix(const SpaceReport& r) {
  const bool monotone = r.analysis.curvature == Direction::increasing || r.analysis.curvature == Direction::decreasing;
  return r.spline && !(monotone || r.near_constant);
}

/// A curve's points in the order their thumbnails matter: the fix's point,
/// then the points acting on a failing segment (each segment's d + 1), then
/// the others; unique points (a closed curve's twins folded).
std::vector<int> thumbnail_order(const SpaceReport& r) {
  const SpaceSpline& s = *r.spline;
  const int m = s.unique_point_count(), d = s.degree();
  std::vector<int> order;
  std::vector<bool> taken(static_cast<std::size_t>(m), false);
  const auto take = [&](int k) {
    k = ((k % m) + m) % m;
    if (!taken[static_cast<std::size_t>(k)]) taken[static_cast<std::size_t>(k)] = true, order.push_back(k);
  };
  if (r.fix && r.fix->fixed && !r.fix->moves.empty()) take(r.fix->moves.front().point);
  for (std::size_t i = 0; i < r.analysis.segments.size(); ++i) {
    const Curvature c = r.analysis.segments[i].curvature.curvature;
    if (c == Curvature::increasing || c == Curvature::decreasing || c == Curvature::constant) continue;
    const int first = s.segments()[i].span - d + 1;
    for (int k = first; k <= first + d; ++k) take(k);
  }
  for (int k = 0; k < m; ++k) take(k);
  return order;
}

}  // namespace

void space_report_extras(std::vector<SpaceReport>& reports, const SpaceReportOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  // The curves by their cost, cheapest first (a stable order: the run's
  // within equal costs), so that the budget covers as many curves as it can:
  // a pixel's work grows with lambda3's degree 6d - 11, a fix search's with
  // the segments too.
  std::vector<SpaceReport*> by_cost;
  for (SpaceReport& r : reports)
    if (r.spline) by_cost.push_back(&r);
  const auto cost = [](const SpaceReport* r) {
    const double d = 6.0 * r->spline->degree() - 11;
    return d * d * static_cast<double>(r->spline->segment_count());
  };
  std::stable_sort(by_cost.begin(), by_cost.end(),
                   [&](const SpaceReport* a, const SpaceReport* b) { return cost(a) < cost(b); });
  // Seconds left of the run's budget (options.budget 0: unlimited).
  const auto left = [&](double cap) {
    if (!(options.budget > 0)) return cap;
    return std::min(cap, options.budget - std::chrono::duration<double>(Clock::now() - start).count());
  };
  std::vector<SpaceReport*> order;  // the failing curves first, each group cheapest first
  for (SpaceReport* r : by_cost)
    if (!r->pass) order.push_back(r);
  for (SpaceReport* r : by_cost)
    if (r->pass) order.push_back(r);
  bool spent = false;
  for (SpaceReport* c : order) {
    SpaceReport& r = *c;
    if (options.fixes && needs_fix(r)) {  // the smallest certified fix (design/space_fix.hpp)
      const double seconds = spent ? 0 : left(kReportSpaceFixSeconds);
      if (!(seconds > 0)) {
        spent = true;
        r.fix_not_searched = true;
      } else {
        SpaceFixRequest f;
        f.max_depth = options.max_depth;
        f.time_limit = seconds;
        r.fix = space_fix(*r.spline, f);
        r.fix->reason = options.show_fields(r.fix->reason);
      }
    }
    if (!options.regions) continue;
    for (int k : thumbnail_order(r)) {
      const double seconds = spent ? 0 : left(kDefaultSpaceRegionSeconds);
      if (!(seconds > 0)) {
        spent = true;
        r.regions_not_drawn.push_back(k);
        continue;
      }
      SpaceThumbnail t = space_thumbnail(*r.spline, k, options.region_size, options.max_depth, seconds);
      if (!t.error.empty() && options.budget > 0 && !(left(kDefaultSpaceRegionSeconds) > 0)) {
        spent = true;  // stopped by the budget, not by the region itself
        r.regions_not_drawn.push_back(k);
        continue;
      }
      t.error = options.show_fields(t.error);
      r.thumbnails.push_back(std::move(t));
    }
    std::sort(r.thumbnails.begin(), r.thumbnails.end(),
              [](const SpaceThumbnail& x, const SpaceThumbnail& y) { return x.point < y.point; });
    std::sort(r.regions_not_drawn.begin(), r.regions_not_drawn.end());
  }
}

SpaceReport space_report(const std::string& file, const SpaceReportOptions& options) {
  std::vector<SpaceReport> one{space_report_analysis(file, options)};
  space_report_extras(one, options);
  return std::move(one.front());
}

nlohmann::ordered_json space_fix_json(const SpaceFixResult& f) {
  const auto v3 = [](const Vec3& p) { return nlohmann::ordered_json::array({p.x, p.y, p.z}); };
  nlohmann::ordered_json moves = nlohmann::ordered_json::array();
  for (const SpacePointMove& m : f.moves) {
    std::string name = "P";
    name += std::to_string(m.point);
    moves.push_back({{"point", m.point},
                     {"name", name},
                     {"from", v3(m.from)},
                     {"to", v3(m.to)},
                     {"displacement", v3(m.to - m.from)},
                     {"distance", m.distance},
                     {"relative", m.distance / f.size}});
  }
  nlohmann::ordered_json j = {{"check", "cmrwi"},
                              {"found", f.fixed && !f.already},
                              {"moves", moves},
                              {"max_relative", f.max_distance / f.size},
                              {"seconds", f.seconds},
                              {"failing_segments", f.failing_segments}};
  if (f.fixed)
    j["certificate"] = {{"curvature", to_string(f.certificate.curvature)}};
  else
    j["reason"] = f.reason;
  return j;
}

nlohmann::ordered_json space_report_json(const std::vector<SpaceReport>& reports, const SpaceReportOptions& options,
                                         const std::vector<std::vector<Finding>>* findings) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  int pass = 0, fail = 0, invalid = 0, finding_count = 0;
  for (std::size_t at = 0; at < reports.size(); ++at) {
    const SpaceReport& r = reports[at];
    nlohmann::ordered_json j = {{"id", "s" + std::to_string(at)}, {"file", r.file}};
    j["status"] = !r.error.empty() ? "invalid" : (r.pass ? "pass" : "fail");
    if (!r.error.empty()) {
      j["error"] = r.error;
      ++invalid;
      list.push_back(j);
      continue;
    }
    j["name"] = r.spline->name();
    j["pass"] = r.pass;
    j["check_pass"] = r.check_pass;
    j["near_constant"] = r.near_constant;
    j["kappa_spread"] = r.spread;
    j["turning_deviation"] = r.deviation;
    j["analysis"] = space_analysis_json(*r.spline, r.analysis);
    for (std::size_t i = 0; i < r.kappa_spread.size(); ++i) {
      j["analysis"]["segments"][i]["kappa_spread"] = r.kappa_spread[i];
      const double d = r.turning_deviation[i];
      j["analysis"]["segments"][i]["turning_deviation"] = std::isfinite(d) ? nlohmann::ordered_json(d) : nlohmann::ordered_json(nullptr);
      j["analysis"]["segments"][i]["near_constant"] = d <= options.constant_tolerance;
    }
    nlohmann::ordered_json gates = nlohmann::ordered_json::array();
    for (const GateResult& g : r.gates) {
      nlohmann::ordered_json vs = nlohmann::ordered_json::array();
      for (const GateViolation& v : g.violations) {
        nlohmann::ordered_json x = {{"t", v.t}, {"message", v.message}};
        if (v.segment >= 0) x["segment"] = v.segment;
        if (v.joint >= 0) x["joint"] = v.joint;
        vs.push_back(x);
      }
      gates.push_back({{"gate", to_string(g.gate)}, {"pass", g.pass()}, {"violations", vs}});
    }
    j["gates"] = gates;
    if (findings && at < findings->size()) {
      nlohmann::ordered_json fj = nlohmann::ordered_json::array();
      for (const Finding& f : (*findings)[at])
        fj.push_back({{"gate", f.gate}, {"node", f.node}, {"message", f.message}, {"key", f.key()}});
      finding_count += static_cast<int>(fj.size());
      j["findings"] = fj;
    }
    nlohmann::ordered_json ex = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < r.extrema.size(); ++i)
      for (const SpaceExtremum& e : r.extrema[i])
        ex.push_back({{"segment", i}, {"t", e.t}, {"kind", e.maximum ? "max" : "min"},
                      {"kappa", space_curvature(*r.spline, e.t)}});
    j["curvature_extrema"] = ex;
    j["kappa_range"] = {r.kappa_min, r.kappa_max};
    if (options.regions) {  // each point's region in its default plane (the thumbnails)
      nlohmann::ordered_json regions = nlohmann::ordered_json::array();
      for (const SpaceThumbnail& t : r.thumbnails) {
        nlohmann::ordered_json g = {{"point", t.point}};
        if (!t.error.empty()) {
          g["error"] = t.error;
        } else {
          const View& v = t.image.view;
          g["plane"] = {{"origin", vec3_json(t.plane.origin)}, {"u", vec3_json(t.plane.u)}, {"v", vec3_json(t.plane.v)}};
          g["view"] = {v.x0, v.y0, v.x1, v.y1};
          g["size"] = {t.image.width, t.image.height};
          nlohmann::ordered_json counts;
          std::vector<std::uint64_t> n(kRegionLabelCodes, 0);
          for (std::size_t i = 0; i < t.image.size(); ++i) ++n[t.image.code_at(i)];
          for (std::uint8_t l = 0; l < kRegionLabelCodes; ++l) counts[t.image.label_name(l)] = n[l];
          g["counts"] = counts;
        }
        regions.push_back(g);
      }
      j["regions"] = regions;
      if (!r.regions_not_drawn.empty())
        j["regions_not_drawn"] = {{"points", r.regions_not_drawn}, {"reason", options.show_fields(budget_spent(options))}};
    }
    if (r.fix) j["certified_fixes"] = nlohmann::ordered_json::array({space_fix_json(*r.fix)});
    if (r.fix_not_searched) j["fix_not_searched"] = options.show_fields(budget_spent(options));
    ++(r.pass ? pass : fail);
    list.push_back(j);
  }
  nlohmann::ordered_json doc = {{"schema", kSchema}, {"tool", "cmr report"}, {"dimension", 3}, {"depth", options.max_depth}};
  if (options.require_monotone) doc["require"] = options.require_no_zero_curvature ? "cmr" : "cmrwi";
  nlohmann::ordered_json gate_names = nlohmann::ordered_json::array();
  for (const Gate& g : options.gates) gate_names.push_back(to_string(g));
  doc["gates"] = gate_names;
  doc["constant_tolerance"] = options.constant_tolerance;
  if (options.regions) doc["region_size"] = options.region_size;
  doc["splines"] = list;
  doc["summary"] = {{"splines", reports.size()}, {"pass", pass},           {"fail", fail},
                    {"invalid", invalid},        {"files", reports.size()}, {"findings", finding_count}};
  return doc;
}

namespace {

/// One orthographic view: the two coordinates shown (0 x, 1 y, 2 z).
struct Projection {
  int h, v;
  const char* name;
};

std::string projections_svg(const SpaceSpline& s, double comb_scale) {
  const Projection views[3] = {{0, 1, "top (x, y)"}, {0, 2, "front (x, z)"}, {1, 2, "side (y, z)"}};
  // Sample the curve and its comb (principal normal N = c x P' normalised, length kappa * comb_scale).
  std::vector<Vec3> curve, comb;
  for (const Segment& seg : s.segments())
    for (int i = 0; i <= 48; ++i) {
      const double t = seg.a + (seg.b - seg.a) * i / 48.0;
      const Vec3 p = evaluate(s, t), d1 = derivative(s, t, 1), d2 = derivative(s, t, 2);
      const Vec3 n = glm::cross(glm::cross(d1, d2), d1);
      const double len = glm::length(n);
      curve.push_back(p);
      comb.push_back(len > 0 ? p + (space_curvature(s, t) * comb_scale / len) * n : p);
    }
  std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"780\" height=\"270\" viewBox=\"0 0 780 270\">";
  for (int k = 0; k < 3; ++k) {
    const Projection& pr = views[k];
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    const auto grow = [&](const Vec3& p) {
      lo[0] = std::min(lo[0], p[pr.h]);
      hi[0] = std::max(hi[0], p[pr.h]);
      lo[1] = std::min(lo[1], p[pr.v]);
      hi[1] = std::max(hi[1], p[pr.v]);
    };
    for (const Vec3& p : curve) grow(p);
    for (const Vec3& p : comb) grow(p);
    for (const Vec3& p : s.points()) grow(p);
    const double ext = std::max({hi[0] - lo[0], hi[1] - lo[1], 1e-12});
    const double scale = 230 / ext, ox = 260.0 * k + 15, oy = 250;
    const auto X = [&](const Vec3& p) { return num(ox + (p[pr.h] - lo[0]) * scale); };
    const auto Y = [&](const Vec3& p) { return num(oy - (p[pr.v] - lo[1]) * scale); };
    out += "<g><text x=\"" + num(ox) + "\" y=\"14\" font-size=\"11\">" + pr.name + "</text>";
    for (std::size_t i = 0; i < curve.size(); i += 2)
      out += "<line x1=\"" + X(curve[i]) + "\" y1=\"" + Y(curve[i]) + "\" x2=\"" + X(comb[i]) + "\" y2=\"" + Y(comb[i]) +
             "\" stroke=\"#7aa7d9\" stroke-width=\"0.7\"/>";
    std::string poly, path, tips;
    for (int i = 0; i < s.unique_point_count(); ++i) poly += X(s.points()[i]) + "," + Y(s.points()[i]) + " ";
    if (s.closed()) poly += X(s.points()[0]) + "," + Y(s.points()[0]);
    for (const Vec3& p : curve) path += X(p) + "," + Y(p) + " ";
    for (const Vec3& p : comb) tips += X(p) + "," + Y(p) + " ";
    out += "<polyline points=\"" + poly + "\" fill=\"none\" stroke=\"#999\" stroke-dasharray=\"3,2\"/>";
    out += "<polyline points=\"" + tips + "\" fill=\"none\" stroke=\"#2b6cb0\" stroke-width=\"0.8\"/>";
    out += "<polyline points=\"" + path + "\" fill=\"none\" stroke=\"#000\" stroke-width=\"1.6\"/></g>";
  }
  return out + "</svg>";
}

std::string plot_svg(const SpaceSpline& s, const std::vector<std::vector<SpaceExtremum>>& extrema, bool torsion) {
  std::vector<std::pair<double, double>> pts;
  for (const Segment& seg : s.segments())
    for (int i = 0; i <= 64; ++i) {
      const double t = seg.a + (seg.b - seg.a) * i / 64.0;
      const double v = torsion ? space_torsion(s, t) : space_curvature(s, t);
      if (std::isfinite(v)) pts.emplace_back(t, v);
    }
  double lo = 0, hi = 0;
  for (const auto& p : pts) {
    lo = std::min(lo, p.second);
    hi = std::max(hi, p.second);
  }
  if (hi - lo <= 0) hi = lo + 1;
  const double t0 = s.domain_begin(), t1 = s.domain_end();
  const auto X = [&](double t) { return num(40 + (t - t0) / (t1 - t0) * 330); };
  const auto Y = [&](double v) { return num(180 - (v - lo) / (hi - lo) * 160); };
  std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"390\" height=\"200\" viewBox=\"0 0 390 200\">";
  out += "<text x=\"4\" y=\"14\" font-size=\"11\">" + std::string(torsion ? "torsion τ(t)" : "curvature κ(t)") +
         "</text><text x=\"4\" y=\"30\" font-size=\"10\">" + html_escape(num(hi)) + "</text><text x=\"4\" y=\"182\" font-size=\"10\">" +
         html_escape(num(lo)) + "</text>";
  for (const Segment& seg : s.segments())
    out += "<line x1=\"" + X(seg.a) + "\" y1=\"20\" x2=\"" + X(seg.a) + "\" y2=\"180\" stroke=\"#ddd\"/>";
  out += "<line x1=\"40\" y1=\"" + Y(0) + "\" x2=\"370\" y2=\"" + Y(0) + "\" stroke=\"#bbb\"/>";
  std::string path;
  for (const auto& p : pts) path += X(p.first) + "," + Y(p.second) + " ";
  out += "<polyline points=\"" + path + "\" fill=\"none\" stroke=\"" + (torsion ? "#8a4baf" : "#c53030") +
         "\" stroke-width=\"1.5\"/>";
  if (!torsion)
    for (const auto& seg : extrema)
      for (const SpaceExtremum& e : seg)
        out += "<circle cx=\"" + X(e.t) + "\" cy=\"" + Y(space_curvature(s, e.t)) + "\" r=\"3\" fill=\"" +
               (e.maximum ? "#c53030" : "#2b6cb0") + "\"/>";
  return out + "</svg>";
}

}  // namespace

std::string space_report_html(const std::vector<SpaceReport>& reports, const SpaceReportOptions& options) {
  std::string out =
      "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>cmr report: space curves</title><style>"
      "body{font-family:sans-serif;margin:20px;max-width:1100px}table{border-collapse:collapse;margin:6px 0}"
      "td,th{border:1px solid #ccc;padding:2px 6px;font-size:13px}.pass{color:#276749}.fail{color:#c53030}"
      "section{border-top:1px solid #999;margin-top:18px;padding-top:8px}"
      "figure{display:inline-block;margin:4px;vertical-align:top}figcaption{font-size:12px;max-width:200px}</style></head><body>"
      "<h1>cmr report: space curves</h1><p>Curvature monotonicity of |κ| certified per segment (Algorithm 1 on "
      "λ₃ = (|c|²)′|P′|² − 3|c|²(|P′|²)′, c = P′ × P″; exact where error bounds do not decide), depth " +
      std::to_string(options.max_depth) + ". See docs/space.md.</p>";
  for (const SpaceReport& r : reports) {
    out += "<section><h2>" + html_escape(r.spline ? (r.spline->name().empty() ? r.file : r.spline->name()) : r.file) +
           "</h2><p>" + html_escape(r.file) + "</p>";
    if (!r.error.empty()) {
      out += "<p class=\"fail\">invalid: " + html_escape(r.error) + "</p></section>";
      continue;
    }
    const SpaceAnalysis& a = r.analysis;
    // The planar report's wording (report_json.cpp, verdict_label): a curve of
    // straights is "straight"; here a curve of constant curvature within
    // --constant-tol says so, and torsion zero on every piece is "zero".
    bool straight = !a.segments.empty();
    for (const SpaceSegmentResult& s : a.segments) straight = straight && s.straight;
    const std::string curvature_label =
        straight ? "straight"
        : r.near_constant && a.curvature != Direction::increasing && a.curvature != Direction::decreasing
            ? "constant within " + num(options.constant_tolerance) + " (turning deviation " + num(r.deviation) + " rad, spread " + num(r.spread) + ")"
            : std::string(to_string(a.curvature));
    out += std::string("<p>curvature: <b class=\"") + (r.pass ? "pass" : "fail") + "\">" + html_escape(curvature_label) +
           "</b>";
    if (a.torsion) out += " · torsion: <b>" + std::string(a.planar ? "zero (planar pieces)" : to_string(*a.torsion)) + "</b>";
    for (const GateResult& g : r.gates)
      out += std::string(" · <span class=\"") + (g.pass() ? "pass" : "fail") + "\">" + html_escape(to_string(g.gate)) +
             (g.pass() ? ": pass" : ": " + std::to_string(g.violations.size()) + " violations") + "</span>";
    out += std::string(" · zero curvature: ") + (a.zero_curvature ? "yes" : "no") + " · cusp: " + (a.cusp ? "yes" : "no") +
           " · κ in [" + html_escape(num(r.kappa_min)) + ", " + html_escape(num(r.kappa_max)) + "]</p>";
    if (r.fix && r.fix->fixed && !r.fix->moves.empty()) {
      const SpacePointMove& m = r.fix->moves.front();
      const Vec3 dm = m.to - m.from;
      out += "<p>Smallest certified fix (cmrwi): move P";
      out += std::to_string(m.point);
      out += " by (" + html_escape(num(dm.x)) + ", " + html_escape(num(dm.y)) + ", " + html_escape(num(dm.z));
      out += "), " + html_escape(num(100 * m.distance / r.fix->size));
      out += "% of the curve size; re-analysed: <b class=\"pass\">";
      out += to_string(r.fix->certificate.curvature);
      out += "</b></p>";
    } else if (r.fix && !r.fix->fixed) {
      out += "<p>No certified fix: " + html_escape(r.fix->reason) + "</p>";
    } else if (r.fix_not_searched) {
      out += "<p>No fix searched: " + html_escape(options.show_fields(budget_spent(options))) + ".</p>";
    }
    const double extent = [&] {
      Vec3 lo = r.spline->points()[0], hi = lo;
      for (const Vec3& p : r.spline->points()) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
      return glm::length(hi - lo);
    }();
    out += projections_svg(*r.spline, r.kappa_max > 0 ? 0.25 * extent / r.kappa_max : 0.0);
    out += "<div>" + plot_svg(*r.spline, r.extrema, false) + (a.torsion && !a.planar ? plot_svg(*r.spline, r.extrema, true) : "") +
           "</div>";
    out += "<table><tr><th>segment</th><th>interval</th><th>curvature</th><th>depth</th><th>κ = 0 at</th>"
           "<th>extrema</th><th>torsion</th><th>exact</th></tr>";
    for (std::size_t i = 0; i < a.segments.size(); ++i) {
      const SpaceSegmentResult& s = a.segments[i];
      const Segment& seg = r.spline->segments()[i];
      std::string zeros, ex;
      for (double t : s.zero_curvature) zeros += num(t) + " ";
      for (const SpaceExtremum& e : r.extrema[i]) ex += std::string(e.maximum ? "max " : "min ") + num(e.t) + " ";
      out += "<tr><td>" + std::to_string(i) + "</td><td>[" + num(seg.a) + ", " + num(seg.b) + "]</td><td>" +
             to_string(s.curvature.curvature) + "</td><td>" + std::to_string(s.curvature.depth) + "</td><td>" + zeros +
             "</td><td>" + ex + "</td><td>" + (s.torsion ? to_string(s.torsion->curvature) : "") + "</td><td>" +
             (s.exact_used ? "yes" : "no") + "</td></tr>";
    }
    out += "</table>";
    std::vector<SpaceJoint> joints = a.joints;
    if (a.seam) joints.push_back(*a.seam);
    if (!joints.empty()) {
      out += "<table><tr><th>joint</th><th>knot</th><th>C</th><th>G1</th><th>G2</th><th>κ left</th><th>κ right</th>"
             "<th>jump</th><th>τ left</th><th>τ right</th></tr>";
      for (const SpaceJoint& j : joints)
        out += "<tr><td>" + std::to_string(j.index) + "</td><td>" + num(j.knot) + "</td><td>C" +
               std::to_string(j.continuity) + "</td><td>" + (j.g1 ? "yes" : "no") + "</td><td>" + (j.g2 ? "yes" : "no") +
               "</td><td>" + num(j.kappa_left) + "</td><td>" + num(j.kappa_right) + "</td><td>" +
               (j.jump > 0 ? "up" : (j.jump < 0 ? "down" : "none")) + "</td><td>" + num(j.tau_left) + "</td><td>" +
               num(j.tau_right) + "</td></tr>";
      out += "</table>";
    }
    if (!r.thumbnails.empty() || !r.regions_not_drawn.empty()) {  // each control point's region in its default plane
      out +=
          "<div class=\"regions\"><h3>Regions of the control points</h3><p>Each control point moved in its default "
          "plane (the plane of <code>cmr region FILE " +
          html_escape(options.show_fields(field("point"))) + " K</code> without " +
          html_escape(options.show_fields(field("plane"))) +
          "), coloured by the certified verdict of the whole curve as in <code>cmr region</code>.</p>";
      for (const SpaceThumbnail& t : r.thumbnails) {
        const std::string p = "P" + std::to_string(t.point);
        out += "<figure>";
        if (t.error.empty())
          out += "<img alt=\"region of " + p + " in " + html_escape(t.plane_name) + "\" width=\"" +
                 std::to_string(options.region_size * 2) + "\" src=\"data:image/png;base64," + base64(t.png) + "\">";
        out += "<figcaption>" + p + ": " + html_escape(t.error.empty() ? "in " + t.plane_name : "no region: " + t.error) +
               "</figcaption></figure>";
      }
      if (!r.regions_not_drawn.empty())
        out += "<p>Not drawn: " + point_ranges(r.regions_not_drawn) + " (" +
               html_escape(options.show_fields(budget_spent(options))) + "; <code>cmr region FILE " +
               html_escape(options.show_fields(field("point"))) + " K</code> draws one).</p>";
      out += "</div>";
    }
    out += "</section>";
  }
  return out + "</body></html>\n";
}

}  // namespace cmr::report
