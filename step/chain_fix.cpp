// Certified fixes of a chain of STEP edges (step/chain_fix.hpp).
#include "step/chain_fix.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "bezierize/space_analyze.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/space.hpp"
#include "spline/spline_json.hpp"

namespace cmr::import {

namespace {

using Clock = std::chrono::steady_clock;

SpaceSpline space_spline_of(const StepCurve& c) {
  return space_spline_from_json(nlohmann::json::parse(step_curve_json(c).dump()));
}

/// The edge's plane when its points lie in one (within 1e-12 of its size):
/// "OX,OY,OZ,UX,UY,UZ,VX,VY,VZ" as `cmr region --plane` takes it (the origin
/// is unused: each moved point is its own); "" when not planar.
std::string plane_of(const std::vector<glm::dvec3>& p) {
  if (p.size() < 3) return "";
  glm::dvec3 lo = p.front(), hi = lo;
  for (const glm::dvec3& q : p) lo = glm::min(lo, q), hi = glm::max(hi, q);
  const double size = glm::length(hi - lo);
  if (!(size > 0)) return "";
  std::size_t a = 0;  // the point farthest from p[0]
  for (std::size_t i = 1; i < p.size(); ++i)
    if (glm::length(p[i] - p[0]) > glm::length(p[a] - p[0])) a = i;
  const glm::dvec3 u = glm::normalize(p[a] - p[0]);
  std::size_t b = 0;  // the point farthest from the line p[0] p[a]
  double far = 0;
  for (std::size_t i = 1; i < p.size(); ++i) {
    const glm::dvec3 d = p[i] - p[0];
    const double off = glm::length(d - glm::dot(d, u) * u);
    if (off > far) far = off, b = i;
  }
  if (!(far > 1e-12 * size)) return "";  // the points are on a line: no plane of their own
  const glm::dvec3 n = glm::normalize(glm::cross(u, p[b] - p[0]));
  for (const glm::dvec3& q : p)
    if (std::abs(glm::dot(q - p[0], n)) > 1e-12 * size) return "";
  const glm::dvec3 v = glm::cross(n, u);
  char buf[256];
  std::snprintf(buf, sizeof buf, "0,0,0,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", u.x, u.y, u.z, v.x, v.y, v.z);
  return buf;
}

/// analyze_space's verdict in a designer's words: its "none" is "not monotone".
std::string verdict_text(Direction d) { return d == Direction::none ? "not monotone" : to_string(d); }

std::string levels_text(int level) {
  std::string s = level == 0 ? "not G1" : "G";
  if (level > 0) s += std::to_string(level);
  return s;
}

}  // namespace

std::vector<int> chain_held_points(const StepCurve& c, int keep) {
  const int m = static_cast<int>(c.points.size()), d = c.degree;
  const auto& k = c.knots;
  const bool clamped_start = k.size() >= static_cast<std::size_t>(d) && k[0] == k[static_cast<std::size_t>(d) - 1];
  const bool clamped_end = k.size() >= static_cast<std::size_t>(d) && k.back() == k[k.size() - static_cast<std::size_t>(d)];
  const int start = clamped_start ? keep : d, end = clamped_end ? keep : d;
  std::vector<int> held;
  for (int i = 0; i < m; ++i)
    if (i <= start || i >= m - 1 - end) held.push_back(i);
  return held;
}

ChainFixResult fix_step_chain(const StepCurves& curves, std::size_t chain_index, const ChainFixRequest& request,
                              const ChainTolerances& tolerances) {
  const auto t0 = Clock::now();
  if (chain_index >= curves.chains.size())
    throw InputError("chain " + std::to_string(chain_index + 1) + " is not a chain of the model (it has " +
                     std::to_string(curves.chains.size()) + (curves.chains.size() == 1 ? " chain)" : " chains)"));
  if (request.keep < 0 || request.keep > 3)
    throw InputFieldError(field("keep") + ": " + std::to_string(request.keep) + " is not a jet order 0..3 (none, g1, g2, g3)");
  const StepChain& chain = curves.chains[chain_index];
  for (std::size_t i : chain.curves)
    if (curves.curves[i].closed)
      throw InputError("chain " + std::to_string(chain_index + 1) + ": " + step_edge_id(curves.curves[i]) +
                       " is a closed edge (a chain fix holds each edge's two ends)");

  ChainFixResult r;
  r.curves = curves;
  r.junctions_before = step_chain_junctions(curves, chain, tolerances);
  bool all_pass = true, any_moved = false;
  std::vector<std::string> failures;
  for (std::size_t i = 0; i < chain.curves.size(); ++i) {
    ChainEdgeFix e;
    e.curve = chain.curves[i];
    StepCurve& c = r.curves.curves[e.curve];
    e.held = chain_held_points(c, request.keep);
    SpaceAnalyzeOptions o;
    o.max_depth = request.max_depth;
    const SpaceSpline spline = space_spline_of(c);
    const SpaceAnalysis before = analyze_space(spline, o);
    e.before = e.after = verdict_text(before.curvature);
    // |kappa| monotone (CMRWI rules: constant counts as monotone); for cmr, no zero curvature and no cusp.
    if (!space_fix_passes(before, request.no_zero_curvature)) {
      e.searched = true;
      SpaceFixRequest q;
      q.no_zero_curvature = request.no_zero_curvature;
      q.held = e.held;
      q.plane_text = plane_of(c.points);
      q.keep = request.keep >= 2 ? Keep::g2 : request.keep == 1 ? Keep::g1 : Keep::none;  // the edge's own joints
      q.max_move = request.max_move;
      q.tolerance = request.tolerance;
      q.max_depth = request.max_depth;
      q.time_limit = request.time_limit;
      SpaceFixResult f = space_fix(spline, q);
      if (f.fixed && f.spline && f.certificate_holds) {
        const SpaceSpline& moved = *f.spline;
        for (std::size_t p = 0; p < c.points.size(); ++p) c.points[p] = moved.points()[p];
        e.after = verdict_text(f.certificate.curvature);
        any_moved = any_moved || !f.moves.empty();
      } else {
        all_pass = false;
        e.reason = f.reason;
        failures.push_back(step_edge_id(c) + ": " + f.reason);
      }
      e.fix = std::move(f);
    }
    c.curvature = to_string(e.fix && e.fix->fixed ? e.fix->certificate.curvature : before.curvature);
    r.edges.push_back(std::move(e));
  }
  r.junctions_after = step_chain_junctions(r.curves, chain, tolerances);
  r.already = all_pass && !any_moved;

  // Every junction keeps its level up to G_keep (OpenCASCADE's derivatives of the fixed edges).
  std::string broken;
  for (std::size_t j = 0; j < r.junctions_before.size(); ++j) {
    const int want = std::min(r.junctions_before[j].level, request.keep);
    if (r.junctions_after[j].level < want) {
      if (!broken.empty()) broken += ", ";
      broken += chain_edge_label(curves, chain, j) + " > " + chain_edge_label(curves, chain, (j + 1) % chain.curves.size()) +
                " " + levels_text(r.junctions_before[j].level) + " -> " + levels_text(r.junctions_after[j].level);
    }
  }
  if (!all_pass) {
    r.reason = "no certified fix of every edge with its ends held (" + field("keep") + " " +
               std::string(request.keep == 0 ? "none" : "g" + std::to_string(request.keep)) + "): ";
    for (std::size_t i = 0; i < failures.size(); ++i) r.reason += (i ? "; " : "") + failures[i];
  } else if (!broken.empty()) {
    r.reason = "a junction lost its continuity (OpenCASCADE's derivatives of the fixed edges): " + broken;
  } else if (request.whole_chain) {
    StepChain after = chain;
    after.junctions = r.junctions_after;
    const ChainVerdict v = chain_verdict(r.curves, after, tolerances);
    if (!v.one_way) {
      std::string dirs;
      for (std::size_t i = 0; i < v.directions.size(); ++i)
        dirs += (i ? ", " : "") + chain_edge_label(curves, chain, i) + " " + v.directions[i];
      r.reason = "each edge is monotone" + std::string(any_moved ? " now" : "") +
                 ", but not the whole chain one way (walked along it: " + dirs +
                 (chain.closed ? "; a closed chain" : "") +
                 "); its ends' curvatures are held, so no move of inner points turns an edge round "
                 "(each-piece asks only for each edge)";
    }
  }
  r.fixed = r.reason.empty();
  if (!r.fixed) r.already = false;
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

}  // namespace cmr::import
