#include "report/gates.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <string_view>

#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "report/extremum.hpp"
#include "report/g3.hpp"
#include "report/report.hpp"
#include "report/xy_extrema.hpp"
#include "report/interpolation.hpp"
#include "spline/format.hpp"

namespace cmr::report {
namespace {

std::string num(double v, int precision = 6) { return format_number(v, precision); }

const char* kGateNames =
    "curvature-extrema-at-nodes, curvature-extrema-at-nodes:runs, max-extrema-per-segment:N, "
    "g2-at-smooth-nodes[:tol], g3-at-smooth-nodes[:tol], no-inflection, each-piece, xy-extrema-at-nodes[:U], g1-between-masters[:DEG], curvature-between-masters, extrema-between-masters; extrema-at-nodes is an alias of "
    "curvature-extrema-at-nodes";

/// Where a curve event lies, for a violation.
GateViolation at_event(const SplineReport& r, const CurveEvent& e, const std::string& what) {
  GateViolation v;
  v.segment = e.segment;
  v.joint = e.joint;
  v.t = e.t;
  if (e.segment >= 0) {
    const Segment& s = r.spline->segments()[e.segment];
    v.local_t = (e.t - s.a) / (s.b - s.a);
    v.message = what + " inside segment " + std::to_string(e.segment) + " at t = " + num(e.t) + " (" +
                num(v.local_t, 3) + " of the segment)";
  } else {
    v.message = what + " at joint " + std::to_string(e.joint) + " (t = " + num(e.t) + ")";
  }
  return v;
}

/// An extremum inside a segment whose curvature varies by more than the
/// report's constant tolerance: the extremum gates judge only those (a
/// rounded circle arc's stationary point is no designed extremum).
bool inside_varying(const SplineReport& r, const CurveEvent& e) {
  return e.segment >= 0 && !r.spans[e.segment].near_constant;
}

}  // namespace

std::string canonical_gate_name(const std::string& text) {
  // The old name, read by fontbakery's users as its x/y-extremes rule, is
  // an alias (kept for command lines and baselines written before the rename).
  static constexpr std::string_view kOld = "extrema-at-nodes";
  if (text.compare(0, kOld.size(), kOld) == 0 && (text.size() == kOld.size() || text[kOld.size()] == ':'))
    return "curvature-" + text;
  return text;
}

std::optional<Gate> parse_gate(const std::string& given) {
  const std::string text = canonical_gate_name(given);
  const std::size_t colon = text.find(':');
  const std::string head = text.substr(0, colon);
  const std::string arg = colon == std::string::npos ? "" : text.substr(colon + 1);
  Gate g;
  if (text == "curvature-extrema-at-nodes:runs") {
    g.kind = Gate::Kind::unimodal_runs;
    return g;
  }
  if (head == "g1-between-masters" && colon != std::string::npos) {
    g.kind = Gate::Kind::g1_between_masters;
    const auto [end, ec] = std::from_chars(arg.data(), arg.data() + arg.size(), g.turn_degrees);
    if (arg.empty() || ec != std::errc() || end != arg.data() + arg.size() || !std::isfinite(g.turn_degrees) ||
        g.turn_degrees < 0 || g.turn_degrees >= 90)
      throw InputFieldError(field("require") + ": '" + text +
                            "' needs a turn in degrees, 0 <= DEG < 90 (g1-between-masters:0.5)");
    return g;
  }
  if (head == "curvature-extrema-at-nodes" || head == "no-inflection" || head == "each-piece" ||
      head == "g1-between-masters" || head == "curvature-between-masters" || head == "extrema-between-masters") {
    if (colon != std::string::npos) throw InputFieldError(field("require") + ": '" + given + "' takes no argument");
    g.kind = head == "no-inflection"        ? Gate::Kind::no_inflection
             : head == "each-piece"         ? Gate::Kind::each_piece
             : head == "g1-between-masters" ? Gate::Kind::g1_between_masters
             : head == "curvature-between-masters" ? Gate::Kind::curvature_between_masters
             : head == "extrema-between-masters"   ? Gate::Kind::extrema_between_masters
                                            : Gate::Kind::extrema_at_nodes;
    return g;
  }
  if (head == "max-extrema-per-segment") {
    g.kind = Gate::Kind::max_extrema_per_segment;
    const auto [end, ec] = std::from_chars(arg.data(), arg.data() + arg.size(), g.max_extrema);
    if (arg.empty() || ec != std::errc() || end != arg.data() + arg.size() || g.max_extrema < 0)
      throw InputFieldError(field("require") + ": '" + text + "' needs a count N >= 0 (max-extrema-per-segment:N)");
    return g;
  }
  if (head == "xy-extrema-at-nodes") {
    g.kind = Gate::Kind::xy_extrema_at_nodes;
    if (colon != std::string::npos) {
      const auto [end, ec] = std::from_chars(arg.data(), arg.data() + arg.size(), g.overshoot);
      if (arg.empty() || ec != std::errc() || end != arg.data() + arg.size() || !std::isfinite(g.overshoot) ||
          g.overshoot < 0)
        throw InputFieldError(field("require") + ": '" + text +
                              "' needs a tolerance U >= 0 in the outline's units (xy-extrema-at-nodes:1)");
    }
    return g;
  }
  if (head == "g2-at-smooth-nodes" || head == "g3-at-smooth-nodes") {
    g.kind = head == "g2-at-smooth-nodes" ? Gate::Kind::g2_at_smooth_nodes : Gate::Kind::g3_at_smooth_nodes;
    if (colon != std::string::npos) {
      const auto [end, ec] = std::from_chars(arg.data(), arg.data() + arg.size(), g.tolerance);
      if (arg.empty() || ec != std::errc() || end != arg.data() + arg.size() || !std::isfinite(g.tolerance) ||
          g.tolerance < 0)
        throw InputFieldError(field("require") + ": '" + text + "' needs a relative tolerance >= 0 (" + head +
                              ":0.05)");
    }
    return g;
  }
  return std::nullopt;
}

const char* severity_note(SeverityOutcome outcome) {
  switch (outcome) {
    case SeverityOutcome::moved: return "";
    case SeverityOutcome::no_allowed_move: return "no allowed move";
    case SeverityOutcome::none_found: return "none found";
  }
  return "";
}

std::string to_string(const Gate& gate) {
  switch (gate.kind) {
    case Gate::Kind::extrema_at_nodes: return "curvature-extrema-at-nodes";
    case Gate::Kind::max_extrema_per_segment: return "max-extrema-per-segment:" + std::to_string(gate.max_extrema);
    case Gate::Kind::g2_at_smooth_nodes: return "g2-at-smooth-nodes:" + num(gate.tolerance);
    case Gate::Kind::g3_at_smooth_nodes: return "g3-at-smooth-nodes:" + num(gate.tolerance);
    case Gate::Kind::no_inflection: return "no-inflection";
    case Gate::Kind::each_piece: return "each-piece";
    case Gate::Kind::unimodal_runs: return "curvature-extrema-at-nodes:runs";
    case Gate::Kind::g1_between_masters:
      return gate.turn_degrees == 0 ? "g1-between-masters" : "g1-between-masters:" + num(gate.turn_degrees);
    case Gate::Kind::curvature_between_masters: return "curvature-between-masters";
    case Gate::Kind::extrema_between_masters: return "extrema-between-masters";
    case Gate::Kind::xy_extrema_at_nodes:
      // The default is the bare name, so that a finding's key (which holds
      // the gate's text) does not change with how the default was spelled.
      return gate.overshoot == kDefaultXyExtremumTolerance ? "xy-extrema-at-nodes"
                                                           : "xy-extrema-at-nodes:" + num(gate.overshoot);
  }
  return {};
}

void parse_require_list(const std::string& text, ReportOptions& options) {
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = text.find(',', pos);
    const std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    pos = comma == std::string::npos ? text.size() + 1 : comma + 1;
    if (std::optional<Gate> g = parse_gate(item)) {
      options.gates.push_back(*g);
      continue;
    }
    Requirement r;
    try {
      r = parse_requirement(item);
    } catch (const InputError& e) {
      if (std::string(e.what()).find("signed curvature") != std::string::npos) throw;  // split:S:max|min: the hint
      if (item == "each-run")  // cmr fix's requirement for a spline file (design/fix.hpp): name the gate it serves
        throw InputFieldError(field("require") + ": each-run is a requirement of `cmr fix` on a spline file; as a "
                              "gate (fonts, reports) it is curvature-extrema-at-nodes:runs");
      throw InputFieldError(field("require") + ": '" + item + "' is not cmrwi, cmr, split:S or a gate (" + kGateNames +
                            ")");
    }
    if (options.require)
      throw InputFieldError(field("require") + ": '" + item + "' and '" + to_string(*options.require) +
                            "': at most one of cmrwi, cmr, split:S");
    options.require = r;
  }
}

std::vector<GateResult> check_gates(const SplineReport& r, const std::vector<Gate>& gates) {
  std::vector<GateResult> out;
  for (const Gate& gate : gates) {
    GateResult g{gate, {}};
    // A curve through infinity fails every gate where it does so.
    for (const SpanReport& span : r.spans)
      if (span.shape.pole) {
        GateViolation v;
        v.segment = span.segment.index;
        v.t = span.shape.poles.front();
        v.local_t = (v.t - span.segment.a) / (span.segment.b - span.segment.a);
        v.message = pole_message(span);
        g.violations.push_back(v);
      }
    switch (gate.kind) {
      case Gate::Kind::extrema_at_nodes:
        for (const CurveEvent& e : r.extrema)
          if (inside_varying(r, e)) g.violations.push_back(at_event(r, e, event_noun(event_kind(r, e))));
        break;
      case Gate::Kind::each_piece:
        // Each judged piece on its own (a one-segment group: no joint inside).
        for (int i = r.analysis.range.first; i <= r.analysis.range.last && !r.analysis.segments.empty(); ++i) {
          const Direction d = part_verdict(r.analysis.segments, r.analysis.joints, i, i + 1, Mode::cmrwi);
          if (d == Direction::increasing || d == Direction::decreasing) continue;
          GateViolation v;
          v.segment = i;
          v.t = r.spline->segments()[i].a;
          v.message = "segment " + std::to_string(i) +
                      (d == Direction::none ? " is not monotone on its own" : " is undecided at the depth limit");
          g.violations.push_back(v);
        }
        break;
      case Gate::Kind::max_extrema_per_segment: {
        std::map<int, std::vector<const CurveEvent*>> per;
        for (const CurveEvent& e : r.extrema)
          if (inside_varying(r, e)) per[e.segment].push_back(&e);
        for (const auto& [segment, events] : per)
          if (static_cast<int>(events.size()) > gate.max_extrema) {
            GateViolation v = at_event(r, *events[gate.max_extrema], "curvature extremum");
            v.message = std::to_string(events.size()) + " curvature extrema inside segment " + std::to_string(segment) +
                        " (at most " + std::to_string(gate.max_extrema) + "); the first extra at t = " + num(v.t);
            g.violations.push_back(v);
          }
        break;
      }
      case Gate::Kind::g2_at_smooth_nodes:
        for (const JointReport& jr : r.joints) {
          if (jr.corner) continue;
          const double kl = jr.joint.kappa_left, kr = jr.joint.kappa_right;
          if (!std::isfinite(kl) || !std::isfinite(kr)) continue;  // a cusp: no curvature to compare
          const double scale = std::max(std::abs(kl), std::abs(kr));
          if (std::abs(kl - kr) > gate.tolerance * scale) {
            GateViolation v;
            v.joint = jr.joint.index;
            v.t = jr.joint.knot;
            v.message = "curvature " + num(kl) + " | " + num(kr) + " at smooth joint " + std::to_string(v.joint) +
                        " (t = " + num(v.t) + "): differs by " + num(100 * std::abs(kl - kr) / scale, 3) + "%";
            g.violations.push_back(v);
          }
        }
        break;
      case Gate::Kind::g3_at_smooth_nodes:
        for (GateViolation& v : g3_violations(r, gate.tolerance)) g.violations.push_back(std::move(v));
        break;
      case Gate::Kind::no_inflection:
        for (const CurveEvent& e : r.inflections) g.violations.push_back(at_event(r, e, "inflection"));
        break;
      case Gate::Kind::unimodal_runs:
        for (GateViolation& v : unimodal_run_violations(r)) g.violations.push_back(std::move(v));
        break;
      case Gate::Kind::xy_extrema_at_nodes:
        for (GateViolation& v : xy_extremum_violations(r, gate.overshoot)) g.violations.push_back(std::move(v));
        break;
      case Gate::Kind::g1_between_masters:
        for (GateViolation& v : g1_between_violations(r, gate.turn_degrees)) g.violations.push_back(std::move(v));
        break;
      case Gate::Kind::curvature_between_masters:
      case Gate::Kind::extrema_between_masters:
        for (GateViolation& v : curvature_between_violations(r, gate.kind == Gate::Kind::extrema_between_masters))
          g.violations.push_back(std::move(v));
        break;
    }
    out.push_back(std::move(g));
  }
  return out;
}

}  // namespace cmr::report
