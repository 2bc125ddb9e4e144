#include "report/certified_fix.hpp"

#include <chrono>

#include "report/glyph_fix.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <sstream>

#include "draw/svg_text.hpp"
#include "io/output.hpp"
#include "report/batch.hpp"
#include "report/report.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "spline/format.hpp"

namespace cmr::report {
namespace {

std::string num(double v) { return format_number(v, 6); }

std::string point_name(int k, const std::vector<std::string>* names) {
  if (names && k >= 0 && k < static_cast<int>(names->size())) return (*names)[k];
  return "P" + std::to_string(k);
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
  request.thread_cpu_clock = true;  // the same fix on a loaded machine
  try {
    FixResult f = fix(spline, request);
    out.size = f.size;
    out.seconds = f.seconds;
    out.failing_segments = f.failing_segments;
    out.found = f.fixed && !f.already;
    out.moves = f.moves;
    if (out.found) {
      out.fixed = std::move(f.spline);
      out.certificate = std::move(f.certificate);
    } else {
      out.reason = f.already ? "the check holds" : options.show_fields(f.reason);
    }
  } catch (const InputError& e) {
    out.reason = options.show_fields(marked_text(e));
  }
  return out;
}

}  // namespace

FixRequest gate_fix_request(const Gate& gate, int max_depth, double max_seconds) {
  FixRequest q;
  q.requirement = requirement_of(gate);
  q.max_depth = max_depth;
  q.keep = Keep::g1;
  q.max_seconds = max_seconds;
  q.threads = 1;
  q.thread_cpu_clock = true;  // the same severity and fix on a loaded machine
  q.grid = 16;
  q.tolerance = 1e-4;
  return q;
}

FixRequirement requirement_of(const Requirement& check) {
  FixRequirement req;
  req.kind = check.split ? FixRequirement::Kind::split
                         : check.mode == Mode::cmr ? FixRequirement::Kind::cmr : FixRequirement::Kind::cmrwi;
  if (check.split) req.split = *check.split;
  req.extremum = check.extremum == Extremum::sharpest   ? FixRequirement::Extremum::sharpest
                 : check.extremum == Extremum::flattest ? FixRequirement::Extremum::flattest
                                                        : FixRequirement::Extremum::any;
  return req;
}

bool has_point_move_fix(const Gate& gate) {
  return gate.kind != Gate::Kind::g3_at_smooth_nodes && gate.kind != Gate::Kind::xy_extrema_at_nodes &&
         !is_interpolation_gate(gate);
}

std::vector<std::string> fixable_checks(const ReportOptions& options) {
  std::vector<std::string> checks;
  for (const Gate& gate : options.gates)
    if (has_point_move_fix(gate)) checks.push_back(to_string(gate));
  if (options.require) checks.push_back(to_string(*options.require));
  return checks;
}

std::string fixable_require(const ReportOptions& options) {
  std::string require;
  for (const std::string& c : fixable_checks(options)) require.append(require.empty() ? "" : ",").append(c);
  return require;
}

FixRequirement requirement_of(const Gate& gate) {
  FixRequirement req;
  switch (gate.kind) {
    case Gate::Kind::extrema_at_nodes:
    case Gate::Kind::max_extrema_per_segment: req.kind = FixRequirement::Kind::extrema_at_nodes; break;
    case Gate::Kind::each_piece: req.kind = FixRequirement::Kind::each_piece; break;
    case Gate::Kind::no_inflection: req.kind = FixRequirement::Kind::no_inflection; break;
    case Gate::Kind::g2_at_smooth_nodes:
      req.kind = FixRequirement::Kind::g2;
      req.g2_tolerance = gate.tolerance;
      break;
    case Gate::Kind::unimodal_runs: req.kind = FixRequirement::Kind::each_run; break;
    case Gate::Kind::g3_at_smooth_nodes:
      throw InputError("g3-at-smooth-nodes has no certified fix (cmr fix keeps g2 at most)");
    case Gate::Kind::xy_extrema_at_nodes:
      // Its fix adds a node (gate_fix says where); no point move implies it.
      throw InputError("xy-extrema-at-nodes is fixed by adding a node at each extremum, not by moving points");
    case Gate::Kind::g1_between_masters:
      throw InputFieldError(to_string(gate) + " is fixed in one master: cmr fix FAMILY.designspace " + field("glyph") +
                            " NAME " + field("require") + " g1-between-masters");
    case Gate::Kind::curvature_between_masters:
    case Gate::Kind::extrema_between_masters:
      throw InputError(to_string(gate) + " is fixed in the masters, which cmr does not search yet");
  }
  return req;
}

namespace {

/// A gate's fix: the implying requirement's, then the fixed spline re-judged
/// by the gate itself (the report's model and check_gates); a fix the gate
/// still fails is no fix, and the entry says where it fails.
CertifiedFix gate_fix(const BSpline& spline, const GateResult& failing, const ReportOptions& options) {
  const Gate& gate = failing.gate;
  if (gate.kind == Gate::Kind::g3_at_smooth_nodes) {  // no point-move search for dkappa/ds yet
    CertifiedFix out;
    out.check = to_string(gate);
    out.reason = "no certified fix for g3-at-smooth-nodes (cmr fix keeps g2 at most)";
    return out;
  }
  if (gate.kind == Gate::Kind::xy_extrema_at_nodes) {
    // Its fix is a node inserted at each extremum (a de Casteljau split,
    // the same curve), which cmr names and does not write back.
    CertifiedFix out;
    out.check = to_string(gate);
    out.reason = "add a node at each extremum (a de Casteljau split there keeps the curve; cmr does not write new "
                 "nodes back): ";
    for (std::size_t k = 0; k < failing.violations.size(); ++k) {
      const std::string& m = failing.violations[k].message;
      const std::size_t at = m.rfind("add a node at ");
      out.reason += (k ? "; " : "") + (at == std::string::npos ? m : m.substr(at + 14));
      const int seg = failing.violations[k].segment;
      if (seg >= 0 && std::find(out.failing_segments.begin(), out.failing_segments.end(), seg) == out.failing_segments.end())
        out.failing_segments.push_back(seg);
    }
    return out;
  }
  if (is_interpolation_gate(gate)) {
    CertifiedFix out;
    out.check = to_string(gate);
    out.reason = gate.kind == Gate::Kind::g1_between_masters && gate.turn_degrees == 0
                     ? options.show_fields("moves in one master fix it: cmr fix FAMILY.designspace " + field("glyph") +
                                           " NAME " + field("require") + " g1-between-masters (two masters)")
                     : "moves in one master would fix it; cmr does not search them yet";
    return out;
  }
  CertifiedFix out = run_fix(spline, requirement_of(gate), options);
  out.requirement = out.check;
  out.check = to_string(gate);
  const ReportOptions judge = judge_only(options, gate);
  if (!out.found && gate.kind == Gate::Kind::unimodal_runs && !failing.violations.empty()) {
    // each-run asks more than the gate (monotone runs, not rising-then-
    // falling peaks). Then the valleys' own handles, judged by the gate
    // itself on every moved spline (its violation count must fall to 0).
    FixRequest q = gate_fix_request(gate, options.max_depth, kReportFixSeconds);
    std::set<int> handles;
    for (const GateViolation& v : failing.violations) handles.insert(v.handles.begin(), v.handles.end());
    q.points.assign(handles.begin(), handles.end());
    q.together = q.points.size() > 1;
    q.judge = [judge](const BSpline& s) {
      try {
        const SplineReport r = gate_report(s, judge);
        return r.gates.empty() ? 0 : static_cast<int>(r.gates[0].violations.size());
      } catch (const InputError&) {
        return std::numeric_limits<int>::max() / 2;
      }
    };
    try {
      if (!q.points.empty()) {
        FixResult f = fix(spline, q);
        out.seconds += f.seconds;
        if (f.fixed && !f.already) {
          out.found = true;
          out.requirement = out.check + " (judged by the gate)";
          out.moves = f.moves;
          out.reason.clear();
          out.fixed = std::move(f.spline);
          out.certificate = std::move(f.certificate);
        }
      }
    } catch (const InputError&) {
      // no such search (a handle out of range): the reason below
    }
  }
  if (!out.found && gate.kind == Gate::Kind::unimodal_runs && !failing.violations.empty()) {
    // Neither: say where the gate fails.
    const GateViolation& v = failing.violations.front();
    std::string handles;
    for (int h : v.handles) handles += (handles.empty() ? "P" : ", P") + std::to_string(h);
    out.reason += "; each-run (every run between nodes monotone) is stronger than the gate, whose valley is segment " +
                  std::to_string(v.segment) + (handles.empty() ? "" : " (its handles " + handles + ")");
  }
  if (!out.found) return out;
  const SplineReport after = gate_report(*out.fixed, judge);
  if (!after.gates.empty() && !after.gates[0].pass()) {
    out.found = false;
    out.reason = "the certified " + out.requirement + " fix still fails " + out.check + " when re-judged: " +
                 after.gates[0].violations[0].message;
    out.fixed.reset();
  }
  return out;
}

/// Every point that can move (contour_of: not a line's inner point) at an
/// integer: a font's contour, whose fixes land on the grid of 1 unit.
bool on_integer_grid(const import::Contour& c) {
  for (std::size_t k = 0; k < c.font_point.size(); ++k) {
    const Vec2 p = c.spline.points()[k];
    if (c.font_point[k] >= 0 && (p.x != std::floor(p.x) || p.y != std::floor(p.y))) return false;
  }
  return true;
}

/// The glyph fix (report/glyph_fix.hpp) of `options`' checks on `contour`
/// (contour_of the spline), on the grid of 1 unit when it is on the integer
/// grid, in kReportFixSeconds; re-judged check by check.
CertifiedFix glyph_engine_fix(const import::Contour& contour, const ReportOptions& options, std::string check,
                              std::string requirement) {
  const BSpline& spline = contour.spline;
  const auto t0 = std::chrono::steady_clock::now();
  CertifiedFix f;
  f.check = std::move(check);
  f.requirement = std::move(requirement);
  f.size = curve_size(spline);
  import::Glyph g;
  g.name = spline.name();
  g.contours.push_back(contour);
  GlyphFixOptions o;
  o.judge = options;
  o.grid = on_integer_grid(contour) ? 1 : 0;
  o.glyph_work = kReportGlyphWork;
  o.guard_seconds = 2 * kReportFixSeconds;
  o.both_searches = false;  // a suggestion in the report's time; `cmr fix` searches on for a nearer one
  try {
    const ContourFix c = fix_glyph(g, o).front();
    f.rejudged = c.rejudged;
    f.found = c.fixed && !c.already;
    f.reason = c.already ? "passes as it is" : options.show_fields(c.reason);
    f.moves = c.moves;
    if (f.found) {
      BSpline fixed = spline;
      for (const PointMove& m : c.moves) fixed = fixed.with_point(m.point, m.to);
      f.certificate = analyze(fixed, fix_analyze_options(FixRequirement{}, options.max_depth));
      f.fixed = std::move(fixed);
    }
  } catch (const InputError& e) {
    f.reason = options.show_fields(marked_text(e));
  }
  f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return f;
}

/// Every required check at once (check "all: A, B").
CertifiedFix all_checks_fix(const import::Contour& contour, const ReportOptions& options) {
  std::string check = "all:";
  if (options.require) check.append(" ").append(to_string(*options.require));
  for (const Gate& g : options.gates) check.append(check.size() > 4 ? ", " : " ").append(to_string(g));
  return glyph_engine_fix(contour, options, std::move(check), "every check at once (the glyph fix, on the grid)");
}

}  // namespace

std::vector<CertifiedFix> certified_fixes(const SplineReport& r, const ReportOptions& options) {
  std::vector<CertifiedFix> out;
  if (!r.spline || options.segments) return out;  // a judged range: fix() judges the whole spline
  // A font contour's fixes land on its grid, found by the glyph fix: with
  // several checks only the fix of all of them at once (a gate's own fix
  // mostly breaks another, and a designer applies the one), with one that
  // check's. Gates the glyph fix does not search keep their entries.
  const int checks = static_cast<int>(options.gates.size()) + (options.require ? 1 : 0);
  const bool polynomial_closed = r.spline->closed() && !r.spline->is_rational();
  const std::optional<import::Contour> contour =
      polynomial_closed ? std::optional<import::Contour>(contour_of(*r.spline, {})) : std::nullopt;
  const bool font = contour && on_integer_grid(*contour);
  if (!r.requirement_pass && (options.require || options.gates.empty())) {
    const Requirement check = check_of(options);
    if (font && checks <= 1) {
      ReportOptions one = options;
      one.require = check;
      out.push_back(glyph_engine_fix(*contour, one, to_string(check), to_string(check) + " (the glyph fix, on the grid)"));
    } else if (!font) {
      out.push_back(run_fix(*r.spline, requirement_of(check), options));
    }
  }
  for (const GateResult& g : r.gates) {
    if (g.pass()) continue;
    if (!font || !has_point_move_fix(g.gate))
      out.push_back(gate_fix(*r.spline, g, options));
    else if (checks == 1)
      out.push_back(glyph_engine_fix(*contour, options, to_string(g.gate),
                                     to_string(g.gate) + " (the glyph fix, on the grid)"));
  }
  if (checks > 1 && contour) out.push_back(all_checks_fix(*contour, options));
  // The glyph fix's entries: the segments its checks fail (shaded in the
  // "before" panel), the failing gates' violations.
  for (CertifiedFix& f : out) {
    if (f.rejudged.empty() || !f.failing_segments.empty()) continue;
    std::set<int> segments;
    for (const GateResult& g : r.gates)
      if (f.check == to_string(g.gate) || f.check.rfind("all:", 0) == 0)
        for (const GateViolation& v : g.violations)
          if (v.segment >= 0) segments.insert(v.segment);
    f.failing_segments.assign(segments.begin(), segments.end());
  }
  return out;
}

double largest_relative_move(const CertifiedFix& f) {
  double worst = 0;
  for (const PointMove& m : f.moves) worst = std::max(worst, m.distance);
  return f.size > 0 ? worst / f.size : 0.0;
}

nlohmann::ordered_json certified_fix_json(const CertifiedFix& f, const std::vector<std::string>* names) {
  nlohmann::ordered_json moves = nlohmann::ordered_json::array();
  for (const PointMove& m : f.moves)
    moves.push_back({{"point", m.point},
                     {"name", point_name(m.point, names)},
                     {"from", {m.from.x, m.from.y}},
                     {"to", {m.to.x, m.to.y}},
                     {"displacement", {m.to.x - m.from.x, m.to.y - m.from.y}},
                     {"distance", m.distance},
                     {"relative", f.size > 0 ? m.distance / f.size : 0.0}});
  nlohmann::ordered_json j = {{"check", f.check}, {"found", f.found}, {"moves", moves}};
  if (!f.requirement.empty() && f.requirement != f.check) j["requirement"] = f.requirement;
  j["max_relative"] = largest_relative_move(f);
  j["seconds"] = f.seconds;
  j["failing_segments"] = f.failing_segments;
  if (f.found && !f.rejudged.empty()) {  // (none found: nothing was re-judged)
    nlohmann::ordered_json checks = nlohmann::ordered_json::array();
    for (const GateCount& c : f.rejudged) checks.push_back({{"check", c.check}, {"before", c.before}, {"after", c.after}});
    j["rejudged"] = checks;
  }
  if (f.found) {
    nlohmann::ordered_json c = {{"cmrwi", to_string(f.certificate.cmrwi)}, {"cmr", to_string(f.certificate.cmr)}};
    if (f.certificate.split) c["split"] = to_string(*f.certificate.split);
    j["certificate"] = c;
  } else {
    j["reason"] = f.reason;
  }
  return j;
}

namespace {

/// Signed curvature samples of one spline, per segment (NaN near a pole).
std::vector<std::vector<double>> kappa_samples(const BSpline& s, int per_segment) {
  std::vector<std::vector<double>> out;
  for (const Segment& seg : s.segments()) {
    std::vector<double> k(per_segment + 1);
    for (int i = 0; i <= per_segment; ++i) {
      // Just inside the ends: a segment's own one-sided curvature at a joint.
      const double u = std::clamp(static_cast<double>(i) / per_segment, 1e-9, 1 - 1e-9);
      const double kappa = curvature_at(s, seg.a + (seg.b - seg.a) * u).kappa;
      k[i] = std::isfinite(kappa) ? kappa : NAN;
    }
    out.push_back(std::move(k));
  }
  return out;
}

// An SVG path of whole-pixel points: "M x y" then relative "l" steps, a
// point dropped where it continues the previous step's straight line in the
// same direction (flat stretches of the curvature cost nothing), repeated
// points dropped.
std::string compact_path(const std::vector<std::pair<long, long>>& pts) {
  std::vector<std::pair<long, long>> keep;
  for (const auto& p : pts) {
    if (!keep.empty() && keep.back() == p) continue;
    if (keep.size() >= 2) {
      const auto& a = keep[keep.size() - 2];
      const auto& b = keep.back();
      const long ux = b.first - a.first, uy = b.second - a.second, vx = p.first - b.first, vy = p.second - b.second;
      if (ux * vy - uy * vx == 0 && ux * vx + uy * vy > 0) {
        keep.back() = p;  // b lies on the segment a..p
        continue;
      }
    }
    keep.push_back(p);
  }
  if (keep.empty()) return {};
  std::string d = "M" + std::to_string(keep[0].first) + " " + std::to_string(keep[0].second);
  if (keep.size() == 1) return d + "h0";
  d += "l";
  for (std::size_t i = 1; i < keep.size(); ++i) {
    const long dx = keep[i].first - keep[i - 1].first, dy = keep[i].second - keep[i - 1].second;
    if (i > 1 && dx >= 0) d += ' ';
    d += std::to_string(dx);
    if (dy >= 0) d += ' ';
    d += std::to_string(dy);
  }
  return d;
}

}  // namespace

std::string kappa_before_after_svg(const BSpline& before, const BSpline& after, const std::vector<int>& failing,
                                   const std::string& id) {
  // About 56 samples a panel whatever the segment count, drawn on whole
  // pixels with relative moves and collinear points dropped (compact_path):
  // a font page with hundreds of fixes stays small (docs/report.md).
  const int per = std::clamp(56 / std::max(1, before.segment_count()), 4, 32);
  const auto kb = kappa_samples(before, per), ka = kappa_samples(after, per);
  double lo = 0, hi = 0;
  for (const auto* set : {&kb, &ka})
    for (const auto& seg : *set)
      for (double k : seg)
        if (std::isfinite(k)) lo = std::min(lo, k), hi = std::max(hi, k);
  if (!(hi > lo)) hi = lo + 1;
  const double pad = 0.06 * (hi - lo);
  lo -= pad, hi += pad;
  const double W = 300, H = 150, t0 = before.domain_begin(), t1 = before.domain_end();
  auto X = [&](int panel, double t) { return panel * (W + 10) + 5 + (W - 10) * (t - t0) / (t1 - t0); };
  auto Y = [&](double k) { return 20 + (H - 30) * (hi - k) / (hi - lo); };
  // Whole pixels, and each kind of mark once for both panels (one path of
  // subpaths, the attributes once): the frames, the failing segments' bands,
  // the zero lines, the segment joints, then the two curves.
  auto I = [](double v) { return std::to_string(std::lround(v)); };
  const int h = static_cast<int>(H) - 20;
  std::string out = draw::svg_open({{"width", I(2 * W + 10)}, {"height", I(H)}, {"class", "kplot"}});
  std::string frames, bands, zero, labels, joints[2];
  for (int panel = 0; panel < 2; ++panel) {
    const BSpline& s = panel == 0 ? before : after;
    const double x0 = panel * (W + 10);
    frames += "M" + I(x0) + " 15h" + I(W) + "v" + std::to_string(h) + "h-" + I(W) + "z";
    if (panel == 0)
      for (int i : failing)
        if (i >= 0 && i < s.segment_count())
          bands += "M" + I(X(0, s.segments()[i].a)) + " 15H" + I(X(0, s.segments()[i].b)) + "v" + std::to_string(h) +
                   "H" + I(X(0, s.segments()[i].a)) + "z";
    zero += "M" + I(x0 + 5) + " " + I(Y(0)) + "h" + I(W - 10);
    // Both panels' joints in panel 0's frame: equal (a fix moves points,
    // not knots) and an id given, the "after" panel reuses the drawing.
    for (const Segment& seg : s.segments())  // += "M" alone: GCC 12 warns falsely (-Wrestrict) on "M" + string
      joints[panel].append("M").append(I(X(0, seg.a))).append(" 15v").append(std::to_string(h));
    labels += "<text font-size=\"11\" x=\"" + I(x0 + 5) + "\" y=\"11\">" +
              (panel == 0 ? "κ before" : "κ after (certified)") + "</text>";
  }
  out += "<path style=\"fill:#fafafa\" stroke=\"#ccc\" d=\"" + frames + "\"/>";
  if (!bands.empty()) out += "<path style=\"fill:#fde0e0\" d=\"" + bands + "\"/>";
  out += "<path stroke=\"#aaa\" d=\"" + zero + "\"/>";
  const char* dashed = "<path stroke=\"#bbb\" stroke-dasharray=\"3 3\"";
  if (!id.empty() && joints[0] == joints[1]) {
    out += dashed + (" id=\"" + id + "\" d=\"") + joints[0] + "\"/><use href=\"#" + id + "\" x=\"" + I(W + 10) + "\"/>";
  } else {
    out += dashed + std::string(" d=\"") + joints[0] + "\"/>" + dashed + " transform=\"translate(" + I(W + 10) +
           ")\" d=\"" + joints[1] + "\"/>";
  }
  out += labels;
  for (int panel = 0; panel < 2; ++panel) {
    const BSpline& s = panel == 0 ? before : after;
    const auto& ks = panel == 0 ? kb : ka;
    out += "<path fill=\"none\" stroke=\"" + std::string(panel == 0 ? "#c00000" : "#1a7f1a") +
           "\" stroke-width=\"1.4\" d=\"";
    std::vector<std::vector<std::pair<long, long>>> strokes;  // whole-pixel polylines, broken at NaN
    bool pen = false;
    for (std::size_t i = 0; i < ks.size(); ++i) {
      const Segment& seg = s.segments()[i];
      for (int k = 0; k <= per; ++k) {
        if (std::isnan(ks[i][k])) {
          pen = false;
          continue;
        }
        if (!pen) strokes.emplace_back();
        strokes.back().emplace_back(std::lround(X(panel, seg.a + (seg.b - seg.a) * k / per)), std::lround(Y(ks[i][k])));
        pen = true;
      }
    }
    for (const auto& stroke : strokes) out += compact_path(stroke);
    out += "\"/>";
  }
  out += "<text font-size=\"9\" x=\"" + I(2 * W - 90) + "\" y=\"11\">κ " + html_escape(num(lo)) + " … " +
         html_escape(num(hi)) + "</text>";
  out += draw::kSvgClose;
  return out;
}

std::string certified_fix_html(const CertifiedFix& f, const BSpline& original, const std::vector<std::string>* names) {
  std::string out = "<div class=\"cfix\"><p>Smallest certified fix (" + html_escape(f.check) + "): ";
  if (!f.found) return out + html_escape(f.reason) + ".</p></div>";
  for (std::size_t i = 0; i < f.moves.size(); ++i) {
    const PointMove& m = f.moves[i];
    out += std::string(i ? "; " : "") + "move " + html_escape(point_name(m.point, names)) + " by (" +
           num(m.to.x - m.from.x) + ", " + num(m.to.y - m.from.y) + ") to (" + num(m.to.x) + ", " + num(m.to.y) +
           "), " + num(m.distance) + " (" + num(100 * m.distance / f.size) + "% of the curve size)";
  }
  if (f.rejudged.empty()) {
    out += " ✓ certified by analyze (" + num(f.seconds) + " s).</p>";
  } else {  // every check re-judged on the moved spline
    out += ". Re-judged:";
    for (std::size_t i = 0; i < f.rejudged.size(); ++i)
      out += std::string(i ? "," : "") + " " + html_escape(f.rejudged[i].check) + " " +
             std::to_string(f.rejudged[i].before) + " → " + std::to_string(f.rejudged[i].after);
    out += " ✓ (" + num(f.seconds) + " s).</p>";
  }
  if (f.fixed) out += kappa_before_after_svg(original, *f.fixed, f.failing_segments);
  return out + "</div>";
}

}  // namespace cmr::report
