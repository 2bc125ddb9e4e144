#include "report/report.hpp"
#include "report/report_detail.hpp"

#include <algorithm>
#include <charconv>
#include <functional>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "numeric/bernstein.hpp"
#include "bezierize/extract.hpp"
#include "design/fix.hpp"
#include "numeric/fast_roots.hpp"
#include "numeric/tracked.hpp"
#include "bezierize/joint_json.hpp"
#include "bezierize/lambda.hpp"
#include "bezierize/rational_lambda.hpp"
#include "region/region.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"
#include "spline/spline_json.hpp"
#include "draw/draw.hpp"
#include "draw/svg_text.hpp"
#include "io/output.hpp"
#include "report/extremum.hpp"

// The report's HTML page (report.hpp: report_html, report_sections_html,
// report_style) with its inline SVG pictures: the curve with its marks, the
// curvature comb and the curvature plot. The model is in report.cpp.

namespace cmr::report {

using namespace report_detail;  // what the parts share (report_detail.hpp)

// ---------------------------------------------------------------- HTML

namespace {

// Colours shared by the pictures and the page. Extrema by their |kappa|
// reading, the words of the messages and the gates (report/extremum.hpp):
// sharpest red, flattest blue, an extremum at an inflection purple; a signed
// maximum where kappa < 0 is a flattest point, so the signed words would
// contradict the messages.
constexpr const char* kRed = "#d00000";
constexpr const char* kBlue = "#0040d0";
constexpr const char* kGreen = "#108010";
constexpr const char* kPurple = "#8000a0";

const char* extremum_colour(const SplineReport& r, const CurveEvent& e) {
  switch (event_kind(r, e)) {
    case ExtremumKind::sharpest: return kRed;
    case ExtremumKind::flattest: return kBlue;
    case ExtremumKind::inflection: return kPurple;
  }
  return kPurple;
}

void fixed(std::string& out, double v, int decimals = 1) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  out.append(buf, r.ptr);
}

std::string num(double v) {
  if (!std::isfinite(v)) return std::isnan(v) ? "undefined" : (v > 0 ? "∞" : "−∞");
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6);
  return std::string(buf, r.ptr);
}

// Maps world coordinates into an SVG box with a 10 px margin, y up; `left`
// and `bottom` centre content that does not fill the box.
struct Canvas {
  double x0, y0, scale_x, scale_y, height;
  double left = 10, bottom = 10;
  double x(double wx) const { return (wx - x0) * scale_x + left; }
  double y(double wy) const { return height - bottom - (wy - y0) * scale_y; }
};

void point_xy(std::string& out, const Canvas& c, Vec2 p) {
  fixed(out, c.x(p.x));
  out += ',';
  fixed(out, c.y(p.y));
}

void marker(std::string& out, double x, double y, const char* colour, double radius = 4) {
  out += "<circle cx=\"";
  fixed(out, x);
  out += "\" cy=\"";
  fixed(out, y);
  out += "\" r=\"";
  fixed(out, radius);
  out += "\" fill=\"";
  out += colour;
  out += "\"/>";
}

constexpr int kSamples = 24;  // per segment, for the curve, the comb and the plot

/// The curve picture's canvas and its curvature comb: teeth along the
/// normal, away from the centre of curvature, the longest 18% of the extent.
struct CombCanvas {
  Canvas canvas{0, 0, 1, 1, 0};
  double comb = 0;  ///< tooth length per unit of curvature
  Vec2 tip(const Frame& f) const {
    const double len = std::sqrt(dot(f.tangent, f.tangent));
    const Vec2 normal = len > 0 ? Vec2(-f.tangent.y, f.tangent.x) / len : Vec2(0.0);
    return f.point - comb * (std::isfinite(f.kappa) ? f.kappa : 0.0) * normal;
  }
};

/// A canvas of W x H on which the control points, the curve and the comb all fit.
CombCanvas comb_canvas(const BSpline& s, const std::vector<std::vector<Frame>>& frames, double W, double H) {
  Vec2 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  double kmax = 0;
  auto grow = [&](Vec2 p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return;
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  };
  for (const Vec2& p : s.points()) grow(p);
  for (const auto& fs : frames)
    for (const Frame& f : fs) {
      if (!f.drawn) continue;
      grow(f.point);
      if (std::isfinite(f.kappa)) kmax = std::max(kmax, std::fabs(f.kappa));
    }
  CombCanvas cc;
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, 1e-300});
  cc.comb = kmax > 0 ? 0.18 * extent / kmax : 0;
  for (const auto& fs : frames)
    for (const Frame& f : fs)
      if (f.drawn) grow(cc.tip(f));
  const double scale = std::min((W - 20) / std::max(hi.x - lo.x, 1e-300), (H - 20) / std::max(hi.y - lo.y, 1e-300));
  cc.canvas = {lo.x, lo.y, scale, scale, H, 0.5 * (W - (hi.x - lo.x) * scale), 0.5 * (H - (hi.y - lo.y) * scale)};
  return cc;
}

/// An SVG path of one polyline per segment through point(frame), broken
/// where frames are not drawn and where W changes sign (across a pole).
template <class PointOf>
void polylines(std::string& out, const Canvas& c, const std::vector<std::vector<Frame>>& frames, PointOf point) {
  for (const auto& fs : frames) {
    const Frame* last = nullptr;  // the previous frame, while the line goes on
    for (const Frame& f : fs) {
      if (!f.drawn) {
        last = nullptr;
        continue;
      }
      if (!last || (last->weight > 0) != (f.weight > 0)) out += 'M';
      point_xy(out, c, point(f));
      out += ' ';
      last = &f;
    }
  }
}

/// Control point names, and markers at the extrema and inflections.
void curve_marks_svg(std::string& out, const SplineReport& r, const Canvas& c) {
  const BSpline& s = *r.spline;
  for (int k = 0; k < s.point_count(); ++k) {
    const Vec2 p = s.points()[k];
    marker(out, c.x(p.x), c.y(p.y), "#666", 2.5);
    out += "<text font-size=\"10\" fill=\"#444\" x=\"";
    fixed(out, c.x(p.x) + 4);
    out += "\" y=\"";
    fixed(out, c.y(p.y) - 4);
    out += "\">P" + std::to_string(k) + "</text>";
  }
  const CurveSampler sampler(s);
  for (const CurveEvent& e : r.extrema) {
    const Vec2 p = evaluate(s, e.t);
    if (sampler.inside(p)) marker(out, c.x(p.x), c.y(p.y), extremum_colour(r, e), 4.5);
  }
  for (const CurveEvent& e : r.inflections) {
    const Vec2 p = evaluate(s, e.t);
    if (sampler.inside(p)) marker(out, c.x(p.x), c.y(p.y), kGreen, 3.5);
  }
}

/// The curve, its control polygon and its curvature comb.
void curve_svg(std::string& out, const SplineReport& r, const std::vector<std::vector<Frame>>& frames) {
  const CombCanvas cc = comb_canvas(*r.spline, frames, 440, 330);
  const Canvas& c = cc.canvas;
  out += draw::svg_open({{"width", "440"}, {"height", "330"}, {"class", "curve"}});
  out += "<path fill=\"none\" stroke=\"#8fb0e8\" stroke-width=\"1\" d=\"";
  for (const auto& fs : frames)
    for (const Frame& f : fs) {
      if (!f.drawn) continue;
      out += 'M';
      point_xy(out, c, f.point);
      out += 'L';
      point_xy(out, c, cc.tip(f));
    }
  out += "\"/><path fill=\"none\" stroke=\"";
  out += kBlue;
  out += "\" stroke-width=\"1.2\" d=\"";
  polylines(out, c, frames, [&](const Frame& f) { return cc.tip(f); });
  out += "\"/><polyline fill=\"none\" stroke=\"#999\" stroke-dasharray=\"4 3\" points=\"";
  for (const Vec2& p : r.spline->points()) {
    point_xy(out, c, p);
    out += ' ';
  }
  out += "\"/><path fill=\"none\" stroke=\"#111\" stroke-width=\"2\" d=\"";
  polylines(out, c, frames, [](const Frame& f) { return f.point; });
  out += "\"/>";
  curve_marks_svg(out, r, c);
  out += draw::kSvgClose;
}

// Signed curvature against the parameter: knots dashed, extrema as on the
// curve (sharpest red, flattest blue), inflections green.
void plot_svg(std::string& out, const SplineReport& r, const std::vector<std::vector<Frame>>& frames) {
  const BSpline& s = *r.spline;
  const double W = 440, H = 240;
  double klo = std::isfinite(r.kappa_min) ? std::min(r.kappa_min, 0.0) : 0.0;
  double khi = std::isfinite(r.kappa_max) ? std::max(r.kappa_max, 0.0) : 0.0;
  if (!(khi > klo)) khi = klo + 1;
  const double pad = 0.06 * (khi - klo);
  klo -= pad;
  khi += pad;
  const double t0 = s.domain_begin(), t1 = s.domain_end();
  const Canvas c{t0, klo, (W - 20) / (t1 - t0), (H - 20) / (khi - klo), H};
  out += draw::svg_open({{"width", "440"}, {"height", "240"}, {"class", "plot"}});
  out += "<rect x=\"10\" y=\"10\" width=\"420\" height=\"220\" fill=\"#fafafa\" stroke=\"#ccc\"/>";
  out += "<line stroke=\"#aaa\" x1=\"10\" x2=\"430\" y1=\"";
  fixed(out, c.y(0));
  out += "\" y2=\"";
  fixed(out, c.y(0));
  out += "\"/><path stroke=\"#bbb\" stroke-dasharray=\"3 3\" d=\"";
  for (const Segment& seg : s.segments()) {
    out += 'M';
    fixed(out, c.x(seg.a));
    out += ",10V230";
  }
  out += "\"/><path fill=\"none\" stroke=\"#111\" stroke-width=\"1.5\" d=\"";
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const Segment& seg = s.segments()[i];
    bool pen = false;
    for (int k = 0; k <= kSamples; ++k) {
      if (!frames[i][k].drawn) {  // near a pole
        pen = false;
        continue;
      }
      if (!pen) out += 'M';
      pen = true;
      const double kappa = std::clamp(frames[i][k].kappa, klo, khi);  // a cusp's infinity stays on the plot
      fixed(out, c.x(seg.a + (seg.b - seg.a) * k / kSamples));
      out += ',';
      fixed(out, c.y(std::isnan(kappa) ? 0.0 : kappa));
      out += ' ';
    }
  }
  out += "\"/>";
  for (const CurveEvent& e : r.extrema)
    marker(out, c.x(e.t), c.y(std::clamp(e.kappa, klo, khi)), extremum_colour(r, e), 4.5);
  for (const CurveEvent& e : r.inflections) marker(out, c.x(e.t), c.y(0), kGreen, 3.5);
  out += "<text font-size=\"10\" x=\"14\" y=\"22\">κ " + html_escape(num(khi)) + "</text>";
  out += "<text font-size=\"10\" x=\"14\" y=\"226\">κ " + html_escape(num(klo)) + "</text>";
  out += "<text font-size=\"10\" x=\"380\" y=\"226\">t " + html_escape(num(t1)) + "</text>";
  out += draw::kSvgClose;
}

std::string badge(const SplineReport& r) {
  const std::string st = status_word(r);
  std::string label = st;
  std::transform(label.begin(), label.end(), label.begin(), [](unsigned char ch) { return std::toupper(ch); });
  return "<span class=\"badge " + st + "\">" + label + "</span>";
}

std::string roots_cell(const std::vector<SpanRoot>& roots, bool extremum) {
  std::string out;
  for (const SpanRoot& x : roots) {
    if (!out.empty()) out += "<br>";
    const std::string kind = extremum ? root_kind_word(x.sign_before, x.sign_after)
                                      : (x.sign_before != x.sign_after ? "sign change" : "touch");
    out += num(x.t) + (x.exact ? " (exact) " : " ") + kind;
    if (x.multiplicity > 1) out += " ×" + std::to_string(x.multiplicity);
  }
  return out.empty() ? "—" : out;
}

std::string place_text(const CurveEvent& e) {
  return e.joint >= 0 ? "on joint " + std::to_string(e.joint) : "inside segment " + std::to_string(e.segment);
}

/// The verdicts, the size of the spline and its curvature range in one paragraph.
void summary_html(std::string& out, const SplineReport& r, const ReportOptions& options) {
  const BSpline& s = *r.spline;
  out += "<p>check <b>" + html_escape(to_string(check_of(options))) + "</b>: CMRWI " + verdict_label(r, r.analysis.cmrwi) +
         ", CMR " + verdict_label(r, r.analysis.cmr);
  if (r.analysis.split) out += ", split " + std::string(to_string(*r.analysis.split));
  if (r.analysis.range != SegmentRange{0, s.segment_count() - 1})
    out += " (segments " + std::to_string(r.analysis.range.first) + ".." + std::to_string(r.analysis.range.last) +
           " judged, the others ignored)";
  out += ". Degree " + std::to_string(s.degree()) + ", " + std::to_string(s.segment_count()) +
         (s.segment_count() == 1 ? " segment, " : " segments, ") + std::to_string(r.monotone_pieces) +
         " monotone curvature piece" + (r.monotone_pieces == 1 ? "" : "s") +
         (r.cusp ? "; a cusp (zero tangent): κ is unbounded, no finite range.</p>"
                 : "; κ from " + num(r.kappa_min) + " (t = " + num(r.t_min) + ") to " + num(r.kappa_max) +
                       " (t = " + num(r.t_max) + ").</p>");
}

/// One row per segment: its class, decision depths and roots.
void spans_html(std::string& out, const SplineReport& r) {
  out +=
      "<table><tr><th>segment</th><th>interval</th><th>curvature</th><th>inflection</th><th>depth</th>"
      "<th>stationary points of κ</th><th>zeros of κ</th></tr>";
  for (const SpanReport& sp : r.spans) {
    const bool judged = r.analysis.judged(sp.segment.index);
    if (sp.shape.pole) {  // the curve passes through infinity
      out += "<tr><td>" + std::to_string(sp.segment.index) + "</td><td>[" + num(sp.segment.a) + ", " +
             num(sp.segment.b) + "]</td><td colspan=\"5\" class=\"error\">" + html_escape(pole_message(sp)) +
             "</td></tr>";
      continue;
    }
    out += "<tr><td>" + std::to_string(sp.segment.index) + "</td><td>[" + num(sp.segment.a) + ", " + num(sp.segment.b) +
           "]</td><td>" + (judged ? to_string(sp.classification.monotonicity.curvature) : "ignored") + "</td><td>" +
           (judged ? to_string(sp.classification.inflection.inflection) : "ignored") + "</td><td>" +
           (judged ? std::to_string(sp.classification.monotonicity.depth) + " / " +
                         std::to_string(sp.classification.inflection.depth)
                   : "—") +
           "</td><td>" + roots_cell(sp.extrema, true) +
           (sp.near_constant && !sp.lambda_zero ? " (κ constant: turning within " + num(sp.turning_deviation) + " rad)" : "") +
           "</td><td>" + roots_cell(sp.inflections, false) + "</td></tr>";
  }
  out += "</table>";
}

/// One row per joint (none for a single segment).
void joints_html(std::string& out, const SplineReport& r) {
  if (!r.joints.empty()) {
    out +=
        "<table><tr><th>joint</th><th>knot</th><th>multiplicity</th><th>continuity</th><th>G1</th><th>G2</th>"
        "<th>κ left</th><th>κ right</th><th>jump</th></tr>";
    for (const JointReport& j : r.joints)
      out += "<tr><td>" + std::to_string(j.joint.index) + "</td><td>" + num(j.joint.knot) + "</td><td>" +
             std::to_string(j.joint.multiplicity) + "</td><td>" + j.continuity + (j.corner ? " (corner)" : "") +
             "</td><td>" + (j.joint.zero_tangent ? "no (zero tangent)" : (j.joint.g1 ? "yes" : "no")) +
             "</td><td>" + (j.joint.g2 ? "yes" : "no") + "</td><td>" + num(j.joint.kappa_left) + "</td><td>" +
             num(j.joint.kappa_right) + "</td><td>" +
             jump_name(shown_jump(j.joint)) + "</td></tr>";
    out += "</table>";
  }
}

/// The extrema and inflections of the whole curve, in parameter order.
void events_html(std::string& out, const SplineReport& r) {
  out += "<p>Curvature extrema: ";
  if (r.extrema.empty()) out += "none";
  for (std::size_t i = 0; i < r.extrema.size(); ++i) {
    const CurveEvent& e = r.extrema[i];
    out += (i ? "; " : "") +
           std::string(event_kind(r, e) == ExtremumKind::sharpest   ? "<span class=\"max\">sharpest</span>"
                       : event_kind(r, e) == ExtremumKind::flattest ? "<span class=\"min\">flattest</span>"
                                                                    : "<span class=\"min\">inflection</span>") +
           " κ = " + num(e.kappa) + " at t = " + num(e.t) + " (" + place_text(e) + ")";
  }
  out += ". Inflections: ";
  if (r.inflections.empty()) out += "none";
  for (std::size_t i = 0; i < r.inflections.size(); ++i)
    out += (i ? "; " : "") + std::string("t = ") + num(r.inflections[i].t) + " (" + place_text(r.inflections[i]) + ")";
  out += ".</p>";
}

/// Single control points that can fix a failing spline, with their thumbnails.
void fixes_html(std::string& out, const std::vector<Fix>& fixes, const ReportOptions& options) {
  out += "<div class=\"fixes\"><h3>Single control points that can fix it</h3>";
  bool any = false;
  for (const Fix& f : fixes) {
    if (!f.example) continue;
    any = true;
    out += "<figure>";
    if (!f.thumbnail_png.empty())
      out += "<img alt=\"region of P" + std::to_string(f.point) + "\" width=\"" +
             std::to_string(options.region_size * 2) + "\" src=\"data:image/png;base64," + base64(f.thumbnail_png) +
             "\">";
    out += "<figcaption>move P" + std::to_string(f.point) + " into its region, e.g. to (" + num(f.example->x) + ", " +
           num(f.example->y) + ")" + (f.verified ? " ✓" : " (not confirmed by analyze)") + "</figcaption></figure>";
  }
  if (!any) out += "<p>No single control point has a region in the default view.</p>";
  out += "</div>";
}

void section_html(std::string& out, const SplineReport& r, int index, const ReportOptions& options) {
  out += "<section id=\"s" + std::to_string(index) + "\"><h2>" + html_escape(r.name) + " " + badge(r) + "</h2>";
  out += "<p class=\"file\">" + html_escape(r.file) + "</p>";
  if (!r.error.empty()) {
    out += "<p class=\"error\">" + html_escape(r.error) + "</p></section>";
    return;
  }
  std::vector<std::vector<Frame>> frames(r.spans.size());
  for (std::size_t i = 0; i < r.spans.size(); ++i)
    for (int k = 0; k <= kSamples; ++k)
      frames[i].push_back(frame_at(r.spans[i].bezier, r.spans[i].homogeneous, static_cast<double>(k) / kSamples));
  // Near a pole the curve runs off to infinity: those frames are not drawn.
  const CurveSampler sampler(*r.spline);
  for (auto& fs : frames)
    for (Frame& f : fs) f.drawn = sampler.inside(f.point) && std::isfinite(f.tangent.x) && std::isfinite(f.tangent.y);
  summary_html(out, r, options);
  out += "<div class=\"figs\"><figure>";
  curve_svg(out, r, frames);
  out +=
      "<figcaption>Curve, control polygon and curvature comb; sharpest points (largest |κ|) red, flattest "
      "(smallest |κ|) blue, extrema at an inflection purple, inflections green</figcaption></figure><figure>";
  plot_svg(out, r, frames);
  out += "<figcaption>Signed curvature κ(t); knots dashed; extrema coloured as on the curve (by |κ|: a sharpest "
         "point where κ &lt; 0 is a minimum of this plot)</figcaption></figure></div>";

  spans_html(out, r);
  joints_html(out, r);
  events_html(out, r);
  if (r.fixes) fixes_html(out, *r.fixes, options);
  for (const CertifiedFix& f : r.certified_fixes) out += certified_fix_html(f, *r.spline);
  out += "</section>";
}

constexpr const char* kStyle =
    "body{font:14px/1.4 sans-serif;margin:24px;color:#222}"
    "table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid #ccc;padding:2px 8px;text-align:left;"
    "vertical-align:top}th{background:#f0f0f0}"
    ".badge{color:#fff;padding:1px 8px;border-radius:3px;font-size:13px}"
    ".pass{background:#1a7f1a}.fail{background:#d00000}.invalid{background:#666}"
    ".max{color:#d00000}.min{color:#0040d0}.error{color:#a00000;font-family:monospace}"
    ".file{color:#666;font-family:monospace;margin:0}"
    ".figs,.fixes{display:flex;flex-wrap:wrap;gap:12px}.fixes h3{width:100%;margin:4px 0}"
    "figure{margin:0}figcaption{font-size:12px;color:#555;max-width:260px}img{border:1px solid #ccc}"
    "section{border-top:2px solid #ddd;margin-top:24px}";

}  // namespace

std::string report_style() { return kStyle; }

std::string report_sections_html(const std::vector<SplineReport>& reports, int first, const ReportOptions& options) {
  std::string out;
  for (std::size_t i = 0; i < reports.size(); ++i) section_html(out, reports[i], first + static_cast<int>(i), options);
  return out;
}

std::string report_html(const std::vector<SplineReport>& reports, const ReportOptions& options) {
  int pass = 0, fail = 0, invalid = 0;
  for (const SplineReport& r : reports) (!r.error.empty() ? invalid : (r.pass ? pass : fail))++;
  const std::string counts = std::to_string(reports.size()) + (reports.size() == 1 ? " spline: " : " splines: ") +
                             std::to_string(pass) + " pass, " + std::to_string(fail) + " fail, " +
                             std::to_string(invalid) + " invalid";
  std::string out;
  out.reserve(reports.size() * 24000);
  out += "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>cmr report — " + counts +
         "</title><style>";
  out += kStyle;
  out += "</style></head><body><h1>cmr report</h1><p>" + counts + "; check <b>" + html_escape(to_string(check_of(options))) +
         "</b>" + (options.require ? " (required)" : " (not required)") + ", depth " +
         std::to_string(options.max_depth) + ", schema " + kSchema + ".</p>";
  out +=
      "<table class=\"index\"><tr><th>#</th><th>spline</th><th>file</th><th>status</th><th>CMRWI</th><th>CMR</th>"
      "<th>monotone pieces</th></tr>";
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const SplineReport& r = reports[i];
    std::string id = "s";  // built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + string&& here
    id += std::to_string(i);
    out += "<tr><td>" + std::to_string(i) + "</td><td><a href=\"#" + id + "\">" + html_escape(r.name) + "</a></td><td>" +
           html_escape(r.file) + "</td><td>" + badge(r) + "</td>";
    if (r.error.empty())
      out += "<td>" + verdict_label(r, r.analysis.cmrwi) + "</td><td>" + verdict_label(r, r.analysis.cmr) + "</td><td>" +
             std::to_string(r.monotone_pieces) + "</td></tr>";
    else
      out += "<td colspan=\"3\">invalid input</td></tr>";
  }
  out += "</table>";
  for (std::size_t i = 0; i < reports.size(); ++i) section_html(out, reports[i], static_cast<int>(i), options);
  out += "</body></html>\n";
  return out;
}

}  // namespace cmr::report
