#include "report/certified_fix.hpp"

#include <cmath>
#include <sstream>

#include "io/output.hpp"
#include "report/report.hpp"
#include "spline/errors.hpp"

namespace cmr::report {
namespace {

std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

CertifiedFix run_fix(const BSpline& spline, const FixRequirement& requirement, const ReportOptions& options) {
  CertifiedFix out;
  out.check = to_string(requirement);
  FixRequest request;
  request.requirement = requirement;
  request.max_depth = options.max_depth;
  request.keep = Keep::g1;
  request.max_seconds = kReportFixSeconds;
  request.threads = 1;  // the report already runs one spline per core
  try {
    const FixResult f = fix(spline, request);
    out.size = f.size;
    out.found = f.fixed && !f.already;
    out.moves = f.moves;
    if (!out.found) out.reason = f.already ? "the check holds" : f.reason;
  } catch (const InputError& e) {
    out.reason = e.what();
  }
  return out;
}

}  // namespace

std::vector<CertifiedFix> certified_fixes(const SplineReport& r, const ReportOptions& options) {
  std::vector<CertifiedFix> out;
  if (!r.spline || options.segments) return out;  // a judged range: fix() judges the whole spline
  if (!r.requirement_pass && (options.require || options.gates.empty())) {
    const Requirement check = check_of(options);
    FixRequirement req;
    req.kind = check.split ? FixRequirement::Kind::split
                           : check.mode == Mode::cmr ? FixRequirement::Kind::cmr : FixRequirement::Kind::cmrwi;
    if (check.split) req.split = *check.split;
    req.extremum = check.extremum == Extremum::sharpest   ? FixRequirement::Extremum::sharpest
                   : check.extremum == Extremum::flattest ? FixRequirement::Extremum::flattest
                                                          : FixRequirement::Extremum::any;
    out.push_back(run_fix(*r.spline, req, options));
  }
  for (const GateResult& g : r.gates)
    if (!g.pass() && g.gate.kind == Gate::Kind::extrema_at_nodes) {
      FixRequirement req;
      req.kind = FixRequirement::Kind::extrema_at_nodes;
      out.push_back(run_fix(*r.spline, req, options));
    }
  return out;
}

nlohmann::ordered_json certified_fix_json(const CertifiedFix& f) {
  nlohmann::ordered_json moves = nlohmann::ordered_json::array();
  for (const PointMove& m : f.moves)
    moves.push_back({{"point", m.point},
                     {"from", {m.from.x, m.from.y}},
                     {"to", {m.to.x, m.to.y}},
                     {"distance", m.distance},
                     {"relative", f.size > 0 ? m.distance / f.size : 0.0}});
  nlohmann::ordered_json j = {{"check", f.check}, {"found", f.found}, {"moves", moves}};
  if (!f.found) j["reason"] = f.reason;
  return j;
}

std::string certified_fix_html(const CertifiedFix& f) {
  std::string out = "<p class=\"cfix\">Smallest certified fix (" + html_escape(f.check) + "): ";
  if (!f.found) return out + html_escape(f.reason) + ".</p>";
  for (std::size_t i = 0; i < f.moves.size(); ++i) {
    const PointMove& m = f.moves[i];
    out += std::string(i ? "; " : "") + "move P" + std::to_string(m.point) + " by (" + num(m.to.x - m.from.x) + ", " +
           num(m.to.y - m.from.y) + ") to (" + num(m.to.x) + ", " + num(m.to.y) + "), " + num(m.distance) + " (" +
           num(100 * m.distance / f.size) + "% of the curve size)";
  }
  return out + " ✓ certified by analyze.</p>";
}

}  // namespace cmr::report
