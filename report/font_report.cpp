#include "report/font_report.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "bezierize/extract.hpp"
#include "spline/curvature.hpp"
#include "spline/fields.hpp"
#include "draw/svg_text.hpp"
#include "io/masters.hpp"
#include "io/output.hpp"

namespace cmr::report {
namespace {

std::string fmt(double v, int decimals = 1) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

/// One decimal, without a trailing ".0" (and "0" for "-0.0").
std::string short_num(double v) {
  std::string s = fmt(v, 1);
  if (s.size() > 2 && s.compare(s.size() - 2, 2, ".0") == 0) s.resize(s.size() - 2);
  if (s == "-0") s = "0";
  return s;
}

std::string utf8(std::uint32_t c) {
  std::string s;
  if (c < 0x80) {
    s += static_cast<char>(c);
  } else if (c < 0x800) {
    s += static_cast<char>(0xC0 | (c >> 6));
    s += static_cast<char>(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    s += static_cast<char>(0xE0 | (c >> 12));
    s += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    s += static_cast<char>(0xF0 | (c >> 18));
    s += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
    s += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (c & 0x3F));
  }
  return s;
}

std::string code_label(std::uint32_t c) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "U+%04X", static_cast<unsigned>(c));
  return buf;
}

/// A glyph's contours in font units (y up) as SVG elements in a y-down
/// frame: outlines from the segments' own Bezier points (exact for degrees 2
/// and 3), the curvature comb (teeth along the normal, kappa scaled so that
/// the longest tooth is kCombLength of the em) and gate violations in red.
/// The moves of the certified fixes are drawn on the fixed picture only
/// (fixed_glyph_svg).
struct GlyphPicture {
  std::string body;
  double x0 = 0, y0 = 0, x1 = 1, y1 = 1;  // bounding box in font units
};

constexpr double kCombLength = 0.12;

/// The glyph drawing's colours and widths are presentation attributes, not
/// only the page's CSS: the overview's thumbnail is a <use> of the drawing,
/// and the page's style sheet does not reach into a <use> clone (it would
/// draw filled black shapes). Widths in screen pixels at every size.
constexpr const char* kFixedWidth = " vector-effect=\"non-scaling-stroke\"";

/// The certified fix a contour's outline shows: the first one found (the
/// requirement's, else the first failing gate's), or none.
const CertifiedFix* first_fix(const SplineReport& r) {
  for (const CertifiedFix& f : r.certified_fixes)
    if (f.found && f.fixed) return &f;
  return nullptr;
}

std::string xy0(Vec2 p) { return fmt(p.x, 0) + "," + fmt(-p.y, 0); }

/// A closed outline as an SVG path: Q / C from each segment's Bezier points
/// (exact for degrees 2 and 3), a polyline otherwise.
std::string outline_d(const BSpline& s) {
  std::string d;
  for (const Segment& seg : s.segments()) {
    const std::vector<Vec2> B = bezier_segment(s, seg).points;
    if (d.empty()) d = "M" + xy0(B.front());
    if (B.size() == 3) d += " Q" + xy0(B[1]) + " " + xy0(B[2]);
    else if (B.size() == 4) d += " C" + xy0(B[1]) + " " + xy0(B[2]) + " " + xy0(B[3]);
    else
      for (int k = 1; k <= 8; ++k) d += " L" + xy0(evaluate(s, seg.a + (seg.b - seg.a) * k / 8));
  }
  return d + "Z";
}

/// The moves of fixes as arrows: a line from the old to the new position and
/// a dot on the new one, every move of the glyph in two paths (subpaths; the
/// dot a zero-length stroke with round caps), so that the attributes come
/// once per glyph, not once per move. Drawn in the page itself (the fixed
/// picture, never a <use> clone), so the page's style sheet gives the
/// colours (classes f and fp) and the paths carry none.
std::string move_marks(const std::vector<const CertifiedFix*>& fixes) {
  std::string arrows, dots;
  for (const CertifiedFix* f : fixes)
    for (const PointMove& m : f->moves) {
      // Whole units; the arrow as a relative line (fewer digits).
      const long fx = std::lround(m.from.x), fy = std::lround(-m.from.y);
      const long tx = std::lround(m.to.x), ty = std::lround(-m.to.y);
      arrows.append("M").append(std::to_string(fx)).append(",").append(std::to_string(fy));
      arrows.append("l").append(std::to_string(tx - fx)).append(",").append(std::to_string(ty - fy));
      dots.append("M").append(std::to_string(tx)).append(",").append(std::to_string(ty)).append("h0");
    }
  if (arrows.empty()) return {};
  return "<path class=\"f\" d=\"" + arrows + "\"/><path class=\"fp\" d=\"" + dots + "\"/>";
}
constexpr int kCombSamples = 8;  // comb samples per segment at most (the outline's polyline of other degrees)
/// Comb samples of the whole glyph at most: a glyph of many short segments
/// (serifs) gets fewer per segment (at least 2), so that a Latin font's page
/// stays under 2 MB; a glyph of up to 12 segments gets all 8.
constexpr int kCombSamplesPerGlyph = 96;

GlyphPicture glyph_picture(const std::vector<const SplineReport*>& contours, int units_per_em) {
  GlyphPicture g;
  g.x0 = g.y0 = 1e300;
  g.x1 = g.y1 = -1e300;
  auto grow = [&](Vec2 p) {
    g.x0 = std::min(g.x0, p.x), g.x1 = std::max(g.x1, p.x);
    g.y0 = std::min(g.y0, p.y), g.y1 = std::max(g.y1, p.y);
  };
  // Whole font units: the font's own grid (an implied midpoint or a comb
  // tip is off by at most half a unit, far below a pixel of any view).
  auto xy = [](Vec2 p) { return fmt(p.x, 0) + "," + fmt(-p.y, 0); };
  double kmax = 0;
  for (const SplineReport* r : contours) kmax = std::max({kmax, std::abs(r->kappa_min), std::abs(r->kappa_max)});
  const double scale = kmax > 0 ? kCombLength * units_per_em / kmax : 0;
  std::size_t segments = 0;
  for (const SplineReport* r : contours) segments += r->spans.size();
  const int samples =
      std::clamp(kCombSamplesPerGlyph / static_cast<int>(std::max<std::size_t>(1, segments)) / 2 * 2, 2, kCombSamples);
  // Every contour's outline, teeth, tip line and violation dots each in one
  // path of the glyph (subpaths), so that the attributes come once.
  std::string outline, teeth, tips, dots, marks;
  long tooth_x = 0, tooth_y = 0;  // the last tooth's tip
  for (const SplineReport* r : contours) {
    const BSpline& s = *r->spline;
    outline += "M" + xy(r->spans.front().bezier.front());
    bool first_tip = true;
    long last_tip_x = 0, last_tip_y = 0;
    for (const SpanReport& span : r->spans) {
      const auto& B = span.bezier;
      for (const Vec2& p : B) grow(p);
      if (B.size() == 3) outline += " Q" + xy(B[1]) + " " + xy(B[2]);
      else if (B.size() == 4) outline += " C" + xy(B[1]) + " " + xy(B[2]) + " " + xy(B[3]);
      else
        for (int k = 1; k <= kCombSamples; ++k)
          outline += " L" + xy(evaluate(s, span.segment.a + (span.segment.b - span.segment.a) * k / kCombSamples));
      for (int k = 0; k < samples; ++k) {
        const double t = span.segment.a + (span.segment.b - span.segment.a) * k / samples;
        const CurvatureSample c = curvature_at(s, t);
        const Vec2 d1 = derivative(s, t, 1);
        const double len = std::sqrt(dot(d1, d1));
        if (!(len > 0) || !std::isfinite(c.kappa)) continue;
        const Vec2 n(-d1.y / len, d1.x / len);
        const Vec2 tip = c.point - scale * c.kappa * n;  // outside a counter-clockwise bowl
        // Whole units, relative moves ("l dx,dy"): the same pixels in about
        // half the bytes. A tooth at every other sample, the tip line
        // through every sample (a Latin font's page stays under 2 MB with
        // every gate's marks).
        const long px = std::lround(c.point.x), py = std::lround(-c.point.y);
        const long tx = std::lround(tip.x), ty = std::lround(-tip.y);
        // A tooth starts with a relative move from the previous tooth's tip
        // (the same pixels in fewer digits).
        if (k % 2 == 0) {
          if (teeth.empty())
            teeth.append("M").append(std::to_string(px)).append(",").append(std::to_string(py));
          else
            teeth.append("m").append(std::to_string(px - tooth_x)).append(",").append(std::to_string(py - tooth_y));
          teeth.append("l").append(std::to_string(tx - px)).append(",").append(std::to_string(ty - py));
          tooth_x = tx, tooth_y = ty;
        }
        if (first_tip) tips.append("M").append(std::to_string(tx)).append(",").append(std::to_string(ty));
        else tips.append("l").append(std::to_string(tx - last_tip_x)).append(",").append(std::to_string(ty - last_tip_y));
        last_tip_x = tx, last_tip_y = ty;
        first_tip = false;
      }
    }
    outline += "Z";
    // Violations as round dots (zero-length strokes with round caps): a
    // dozen bytes each, where a font has thousands.
    for (const GateResult& gr : r->gates)
      for (const GateViolation& v : gr.violations) {
        const Vec2 p = evaluate(s, v.t);
        dots.append("M").append(std::to_string(std::lround(p.x))).append(",").append(std::to_string(std::lround(-p.y))).append("h0");
      }
  }
  const std::string fixed_width(kFixedWidth);
  std::string comb = "<path class=\"t\" stroke=\"#7aa6d8\" stroke-width=\"0.6\"" + fixed_width + " d=\"" + teeth +
                     "\"/><path class=\"k\" stroke=\"#2a62a8\" stroke-width=\"0.8\"" + fixed_width + " d=\"" + tips + "\"/>";
  if (!dots.empty())
    marks = "<path class=\"v\" stroke=\"#d00000\" stroke-opacity=\".6\" stroke-width=\"7\" stroke-linecap=\"round\"" +
            fixed_width + " d=\"" + dots + "\"/>" + marks;
  const double pad = 0.05 * units_per_em;
  g.x0 -= pad, g.y0 -= pad, g.x1 += pad, g.y1 += pad;
  g.body = "<g><path stroke=\"#000\" stroke-width=\"1.2\"" + fixed_width + " d=\"" + outline + "\"/></g>" + comb + marks;
  return g;
}

/// The fixed glyph beside the original, in the same frame: the original
/// outline (the picture's `<g id="ID-o">`, see svg()) referenced with a
/// dashed, faint `<use>` rather than drawn again, the changed contours as
/// fixed (first_fix) in green over it, and each move as an arrow
/// (move_marks, drawn here: the picture references nothing but ID-o). Empty
/// when no contour has a fix. `id`: the original picture's id.
std::string fixed_glyph_svg(const std::vector<const SplineReport*>& contours, const GlyphPicture& frame, int height,
                            const std::string& id) {
  std::string fixed;
  std::vector<const CertifiedFix*> fixes;
  for (const SplineReport* r : contours)
    if (const CertifiedFix* f = first_fix(*r)) fixed += outline_d(*f->fixed), fixes.push_back(f);
  const std::string marks = move_marks(fixes);
  if (fixes.empty() || marks.empty()) return {};
  const double w = frame.x1 - frame.x0, h = frame.y1 - frame.y0;
  return draw::svg_open({{"height", std::to_string(height)},
                         {"width", std::to_string(static_cast<int>(std::ceil(height * w / h)))},
                         {"viewBox", fmt(frame.x0, 0) + " " + fmt(-frame.y1, 0) + " " + fmt(w, 0) + " " + fmt(h, 0)},
                         {"class", "fixed"}}) +
         "<use href=\"#" + id + "-o\" fill=\"none\" opacity=\".45\" stroke-dasharray=\"4 3\"/><path class=\"x\" d=\"" + fixed +
         "\"/>" + marks +
         std::string(draw::kSvgClose);
}

/// Interpolation gates: the glyph at the two masters of its first
/// violation's piece and at the instance the violation names (the worst or
/// first failing location, (1 - s) A + s B: the motions' unrolled control
/// points, as an open spline on their knots), side by side in one frame,
/// the instance in red with its curvature comb (kCombSamples teeth per
/// segment). Empty without such a violation. `caption`: the violation's
/// message.
std::string between_svg(const std::vector<const SplineReport*>& contours, int units_per_em, int height,
                        std::string& caption) {
  int k = -1;
  double s = 0;
  for (const SplineReport* r : contours)
    for (const GateResult& gr : r->gates)
      for (const GateViolation& v : gr.violations)
        if (k < 0 && v.motion >= 0 && r->motions && v.motion < static_cast<int>(r->motions->size()))
          k = v.motion, s = v.motion_s, caption = v.message;
  if (k < 0) return {};
  std::vector<BSpline> panels[3];  // master a, the instance, master b
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const SplineReport* r : contours) {
    if (!r->motions || k >= static_cast<int>(r->motions->size())) continue;
    const import::ContourMotion& m = (*r->motions)[k];
    if (m.a.is_rational() || m.a.points().size() != m.b.points().size()) continue;
    std::vector<Vec2> pts;
    for (std::size_t i = 0; i < m.a.points().size(); ++i)
      pts.push_back(m.a.points()[i] + s * (m.b.points()[i] - m.a.points()[i]));
    panels[0].push_back(m.a);
    panels[1].push_back(BSpline::make(m.a.degree(), m.a.knots(), pts));
    panels[2].push_back(m.b);
    for (const auto& panel : panels)
      for (const Vec2 q : panel.back().points()) {
        x0 = std::min(x0, q.x), x1 = std::max(x1, q.x);
        y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
      }
  }
  if (panels[1].empty()) return {};
  const double pad = 0.05 * units_per_em, w = x1 - x0 + 2 * pad, h = y1 - y0 + 2 * pad;
  double kmax = 0;
  for (const BSpline& inst : panels[1])
    for (const Segment& seg : inst.segments())
      for (int j = 0; j <= kCombSamples; ++j) {
        const CurvatureSample c = curvature_at(inst, seg.a + (seg.b - seg.a) * j / kCombSamples);
        if (std::isfinite(c.kappa)) kmax = std::max(kmax, std::abs(c.kappa));
      }
  const double scale = kmax > 0 ? kCombLength * units_per_em / kmax : 0;
  std::string body;
  for (int p = 0; p < 3; ++p) {
    std::string d, teeth;
    for (const BSpline& c : panels[p]) {
      d += outline_d(c);
      if (p != 1) continue;
      for (const Segment& seg : c.segments())
        for (int j = 0; j < kCombSamples; ++j) {
          const double t = seg.a + (seg.b - seg.a) * j / kCombSamples;
          const CurvatureSample cs = curvature_at(c, t);
          const Vec2 d1 = derivative(c, t, 1);
          const double len = std::sqrt(dot(d1, d1));
          if (!(len > 0) || !std::isfinite(cs.kappa)) continue;
          const Vec2 tip = cs.point - scale * cs.kappa * Vec2(-d1.y / len, d1.x / len);
          teeth += 'M';  // appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "literal" + string&&
          teeth += xy0(cs.point);
          teeth += 'L';
          teeth += xy0(tip);
        }
    }
    body += "<g transform=\"translate(" + fmt(p * w, 0) + ",0)\"><path class=\"" + std::string(p == 1 ? "b" : "o2") +
            "\" d=\"" + d + "\"/>";
    if (!teeth.empty()) body += "<path class=\"t\" d=\"" + teeth + "\"/>";
    body += "</g>";
  }
  return draw::svg_open({{"height", std::to_string(height)},
                         {"width", std::to_string(static_cast<int>(std::ceil(height * 3 * w / h)))},
                         {"viewBox", fmt(x0 - pad, 0) + " " + fmt(-(y1 + pad), 0) + " " + fmt(3 * w, 0) + " " + fmt(h, 0)},
                         {"class", "between"}}) +
         body + std::string(draw::kSvgClose);
}

/// The picture drawn once (`<g id>` inside the glyph's large view) and the
/// overview's thumbnail as a reference to it (`<use>`): one copy per page.
std::string svg(const GlyphPicture& g, int height, const std::string& id, bool reference) {
  const double w = g.x1 - g.x0, h = g.y1 - g.y0;
  return draw::svg_open({{"height", std::to_string(height)},
                         {"width", std::to_string(static_cast<int>(std::ceil(height * w / h)))},
                         {"viewBox", fmt(g.x0, 0) + " " + fmt(-g.y1, 0) + " " + fmt(w, 0) + " " + fmt(h, 0)}}) +
         (reference ? "<use href=\"#" + id + "\"/>"
                    : "<g id=\"" + id + "\" fill=\"none\"><g id=\"" + id + "-o\">" +
                          (g.body.rfind("<g>", 0) == 0 ? g.body.substr(3) : g.body + "</g>") + "</g>") +
         std::string(draw::kSvgClose);
}

}  // namespace

std::string local_name(const std::string& name, const std::string& glyph, std::size_t contour) {
  const std::string prefix = glyph + "/c" + std::to_string(contour) + "/";
  return name.compare(0, prefix.size(), prefix) == 0 ? name.substr(prefix.size()) : name;
}

namespace {

/// "p5 to p7" (the nodes at the ends of the violation's segment, in the
/// contour named by the section's heading) or "node p5"; the message itself
/// says which segment and where.
std::string where(const GateViolation& v, const std::vector<std::string>& joints, const std::string& glyph,
                  std::size_t contour) {
  const int N = static_cast<int>(joints.size());
  auto local = [&](const std::string& name) { return local_name(name, glyph, contour); };
  if (v.segment >= 0 && N > 0) return local(joints[v.segment]) + " to " + local(joints[(v.segment + 1) % N]);
  if (v.joint >= 0 && N > 0) return "node " + local(joints[v.joint % N]);
  return "t = " + fmt(v.t, 4);
}

/// Violations per gate and contour whose message a font page prints in full.
constexpr std::size_t kFullMessages = 3;

constexpr const char* kStyle =
    "body{font-family:sans-serif;margin:1.5em;color:#222}table{border-collapse:collapse}"
    "th,td{border:1px solid #ccc;padding:3px 6px;text-align:left;vertical-align:middle}"
    "th{background:#eee;cursor:pointer;user-select:none}td.pass{color:#1a7f1a}td.fail{color:#d00000;font-weight:bold}"
    "svg path{fill:none}svg g path{stroke:#000;stroke-width:1.2;vector-effect:non-scaling-stroke}"
    "svg .t{stroke:#7aa6d8;stroke-width:0.6;vector-effect:non-scaling-stroke}"
    "svg .k{stroke:#2a62a8;stroke-width:0.8;vector-effect:non-scaling-stroke}"
    "svg .v{stroke:#d00000;stroke-opacity:.6;stroke-width:7;stroke-linecap:round;vector-effect:non-scaling-stroke}"
    "svg .f{stroke:#0070f0;stroke-width:2;vector-effect:non-scaling-stroke}"
    "svg .fp{stroke:#0070f0;stroke-width:6;stroke-linecap:round;vector-effect:non-scaling-stroke}"
    "svg .o{stroke:#888;stroke-width:1;stroke-dasharray:4 3;vector-effect:non-scaling-stroke}"
    "svg .x{stroke:#1a7f1a;stroke-width:1.6;vector-effect:non-scaling-stroke}"
    "svg .b{stroke:#c00000;stroke-width:1.4;vector-effect:non-scaling-stroke}"
    "svg .o2{stroke:#000;stroke-width:1;vector-effect:non-scaling-stroke}.pics{display:flex;gap:16px}"
    ".pics figure{margin:0}.pics figcaption{font-size:12px;color:#555}"
    "section{margin-top:1.5em;border-top:1px solid #ccc}.ch{font-size:1.4em}"
    "section svg{cursor:zoom-in}section svg.zoom{height:90vh;width:auto;cursor:zoom-out}";

// Sorting (click a header: text or the cell's data-v number) and filtering
// (name substring, status) of the overview table.
constexpr const char* kScript = R"(<script>
const t=document.getElementById('glyphs'),q=document.getElementById('q'),st=document.getElementById('st');
function filter(){const s=q.value.toLowerCase(),w=st.value;for(const r of t.tBodies[0].rows){
r.style.display=(r.dataset.name.toLowerCase().includes(s)&&(!w||r.dataset.status===w))?'':'none';}}
q.oninput=filter;st.onchange=filter;
t.tHead.querySelectorAll('th').forEach((h,i)=>{h.onclick=()=>{const up=h.dataset.dir!=='asc';h.dataset.dir=up?'asc':'desc';
const rows=[...t.tBodies[0].rows];const key=r=>{const c=r.cells[i];return c.dataset.v!==undefined?Number(c.dataset.v):c.textContent;};
rows.sort((a,b)=>{const x=key(a),y=key(b);return (x<y?-1:x>y?1:0)*(up?1:-1);});rows.forEach(r=>t.tBodies[0].appendChild(r));};});
document.querySelectorAll('section svg').forEach(s=>{s.onclick=()=>s.classList.toggle('zoom');});
</script>)";

}  // namespace

std::string glyph_count_text(int glyphs, int glyphs_fail, int contours, int contours_fail) {
  return std::to_string(glyphs) + " glyphs: " + std::to_string(glyphs - glyphs_fail) + " pass, " +
         std::to_string(glyphs_fail) + " fail; " + std::to_string(contours) + " contours: " +
         std::to_string(contours - contours_fail) + " pass, " + std::to_string(contours_fail) + " fail";
}

std::string shell_word(const std::string& word) {
  const bool plain = !word.empty() && std::all_of(word.begin(), word.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '/' || c == '.' || c == '_' || c == '-' || c == '+' || c == ',' || c == ':' || c == '@';
  });
  if (plain) return word;
  std::string out = "'";
  for (const char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

FontInfo font_inputs(const import::Font& font, std::vector<ReportInput>& inputs) {
  FontInfo info{font.path, font.family, font.style, font.units_per_em, font.cubic, {}, font.missing};
  for (const import::Glyph& g : font.glyphs) {
    FontInfo::GlyphEntry e{g.name, g.codepoint, {}, {}, {}, g.source, {}, {}};
    if (!g.error.empty()) {  // a source glyph that cannot be read: one invalid item
      e.items.push_back(inputs.size());
      e.joint_names.emplace_back();
      e.point_names.emplace_back();
      inputs.push_back({font.path + ":" + g.name, std::nullopt, g.error});
    }
    for (const import::Contour& c : g.contours) {
      e.items.push_back(inputs.size());
      e.joint_names.push_back(c.joint_names);
      e.point_names.push_back(c.point_names);
      if (!g.source.empty() && c.index < static_cast<int>(g.point_lines.size())) {
        const std::vector<int>& lines = g.point_lines[c.index];
        auto line_of = [&](int sp) { return sp >= 0 && sp < static_cast<int>(lines.size()) ? lines[sp] : 0; };
        std::vector<int> pl, jl;
        for (int sp : c.source_point) pl.push_back(line_of(sp));
        for (int sp : c.joint_source_point) jl.push_back(line_of(sp));
        e.point_lines.push_back(std::move(pl));
        e.joint_lines.push_back(std::move(jl));
      }
      inputs.push_back({font.path + ":" + c.spline.name(), c.spline, {}});
    }
    info.glyphs.push_back(std::move(e));
  }
  return info;
}

GlyphHtml font_glyph_html(const FontInfo& font, std::size_t fi, std::size_t gi, const std::vector<SplineReport>& reports,
                          const ReportOptions& options) {
  std::string gate_names;
  for (const Gate& g : options.gates) gate_names += (gate_names.empty() ? "" : ", ") + to_string(g);
  if (options.require) gate_names += (gate_names.empty() ? "" : ", ") + to_string(*options.require);
  const auto& g = font.glyphs[gi];
  GlyphHtml h;
  h.contours = static_cast<int>(g.items.size());
  for (std::size_t i : g.items) h.contours_fail += reports[i].error.empty() && reports[i].pass ? 0 : 1;
  h.pass = h.contours_fail == 0;
  std::string& out = h.row;
  std::string& details = h.details;
  const std::string anchor = "g" + std::to_string(fi) + "-" + import::file_stem(g.name);
  std::vector<const SplineReport*> contours;
  for (std::size_t i : g.items)
    if (reports[i].error.empty()) contours.push_back(&reports[i]);
  const char* status = h.pass ? "pass" : "fail";
  out += "<tr data-name=\"" + html_escape(g.name) + "\" data-status=\"" + status + "\"><td class=\"ch\">" +
         html_escape(utf8(g.codepoint)) + "</td><td><a href=\"#" + anchor + "\">" + html_escape(g.name) +
         "</a></td><td data-v=\"" + std::to_string(g.items.size()) + "\">" + std::to_string(g.items.size()) + "</td>";
  std::string picture;
  if (options.regions && !contours.empty()) {
    const GlyphPicture gp = glyph_picture(contours, font.units_per_em);
    out += "<td><a href=\"#" + anchor + "\">" + svg(gp, 96, anchor + "-pic", true) + "</a></td>";
    picture = svg(gp, 320, anchor + "-pic", false);
    const std::string fixed = fixed_glyph_svg(contours, gp, 320, anchor + "-pic");
    if (!fixed.empty())
      picture = "<div class=\"pics\"><figure>" + picture + "<figcaption>original</figcaption></figure><figure>" +
                fixed + "<figcaption>fixed (green) over the original (dashed)</figcaption></figure></div>";
    std::string caption;
    const std::string between = between_svg(contours, font.units_per_em, 320, caption);
    if (!between.empty())
      picture += "<figure>" + between + "<figcaption>between the masters: left and right the masters, in red the "
                 "instance of " + html_escape(caption) + "</figcaption></figure>";
  } else if (options.regions) {
    out += "<td></td>";
  }
  std::size_t fixes = 0;
  for (const SplineReport* r : contours) fixes += first_fix(*r) ? 1 : 0;
  for (std::size_t k = 0; k < options.gates.size(); ++k) {
    std::size_t n = 0;
    for (const SplineReport* r : contours) n += r->gates[k].violations.size();
    out += "<td class=\"" + std::string(n == 0 ? "pass" : "fail") + "\" data-v=\"" + std::to_string(n) + "\">" +
           (n == 0 ? "pass" : std::to_string(n) + " fail") + "</td>";
  }
  // A glyph of straight pieces only (l, I, H, -): constant curvature, labelled so, not by a direction.
  const bool straight = !contours.empty() && std::all_of(contours.begin(), contours.end(),
                                                         [](const SplineReport* r) { return straight_only(*r); });
  out += "<td data-v=\"" + std::to_string(fixes) + "\">" + std::to_string(fixes) + "</td><td class=\"" + status +
         "\">" + status + (straight ? " (straight)" : "") + "</td></tr>";

  details += "<section id=\"" + anchor + "\"><h2>" + html_escape(g.name) + " <span class=\"ch\">" +
             html_escape(utf8(g.codepoint)) + "</span> " + code_label(g.codepoint) + ": " + status + "</h2>" +
             picture;
  for (std::size_t c = 0; c < g.items.size(); ++c) {
    const SplineReport& r = reports[g.items[c]];
    details += "<h3>" + html_escape(r.name) + ": " + (r.error.empty() ? (r.pass ? "pass" : "fail") : "invalid") +
               (straight_only(r) ? ", straight" : "") + "</h3>";
    if (!r.error.empty()) {
      details += "<p>" + html_escape(r.error) + "</p>";
      continue;
    }
    details += "<p>" + std::to_string(r.spline->segment_count()) + " segments, " +
               std::to_string(r.extrema.size()) + " curvature extrema, " + std::to_string(r.inflections.size()) +
               " inflections.</p><ul>";
    // Each gate's first kFullMessages violations in full, then the
    // places of the others in one item (every message is in report.json,
    // JUnit and SARIF): a whole font's page stays small.
    for (const GateResult& gr : r.gates) {
      std::string more;
      for (std::size_t k = 0; k < gr.violations.size(); ++k) {
        const GateViolation& v = gr.violations[k];
        if (k < kFullMessages)
          details += "<li><b>" + html_escape(to_string(gr.gate)) + "</b>: " + html_escape(v.message) + " &mdash; " +
                     html_escape(where(v, g.joint_names[c], g.name, c)) + "</li>";
        else
          more += (more.empty() ? "" : "; ") + html_escape(where(v, g.joint_names[c], g.name, c));
      }
      if (!more.empty())
        details += "<li><b>" + html_escape(to_string(gr.gate)) + "</b>, " +
                   std::to_string(gr.violations.size() - kFullMessages) + " more: " + more + "</li>";
    }
    details += "</ul>";
    for (const CertifiedFix& f : r.certified_fixes) {
      details += "<p>Smallest certified fix (" + html_escape(f.check) + "): ";
      if (!f.found) {
        details += html_escape(f.reason) + ".</p>";
        continue;
      }
      details += std::to_string(f.moves.size()) + (f.moves.size() == 1 ? " point" : " points") +
                 ", largest move " + fmt(100 * largest_relative_move(f), 2) + "% of the contour size, " +
                 fmt(f.seconds, 2) + " s; ";
      if (f.rejudged.empty()) {
        details += "certified by analyze.";
      } else {  // one fix for every check: each re-judged on the moved contour
        details += "re-judged:";
        for (std::size_t i = 0; i < f.rejudged.size(); ++i)
          details += std::string(i ? "," : "") + " " + html_escape(f.rejudged[i].check) + " " +
                     std::to_string(f.rejudged[i].before) + " &rarr; " + std::to_string(f.rejudged[i].after);
        details += ".";
      }
      details += "</p><table><tr><th>move<th>from<th>to<th>distance";
      // The point's own name without the glyph and contour (the
      // heading above says them), whole units without ".0", no "by"
      // column (to minus from; report.json has the displacement) and no
      // optional end tags: a font's page has hundreds of these rows.
      for (const PointMove& m : f.moves) {
        std::string name = "P";
        if (m.point < static_cast<int>(g.point_names[c].size())) name = g.point_names[c][m.point];
        else name.append(std::to_string(m.point));
        name = local_name(name, g.name, c);
        details += "<tr><td>" + html_escape(name) + "<td>" + short_num(m.from.x) + ", " + short_num(m.from.y) +
                   "<td>" + short_num(m.to.x) + ", " + short_num(m.to.y) + "<td>" +
                   short_num(m.distance) + " (" + fmt(100 * m.distance / f.size, 2) + "%)";
      }
      // κ before and after for the fix the outline shows (first_fix) only: a Latin font's page stays small.
      details += "</table>";
      if (&f == first_fix(r))
        details += kappa_before_after_svg(*r.spline, *f.fixed, f.failing_segments, anchor + "-c" + std::to_string(c) + "-j");
    }
  }
  // A source (UFO): the command that writes a fix of every required
  // check a point move can fix back into it, on the grid (cmr fix,
  // docs/fix.md "Font sources"), where the glyph fails one of them.
  const std::string require = fixable_require(options);
  const auto fails_fixable = [&](const SplineReport& r) {
    if (!r.error.empty() || r.pass) return false;
    if (options.require && !r.requirement_pass) return true;
    return std::any_of(r.gates.begin(), r.gates.end(),
                       [](const GateResult& x) { return !x.pass() && has_point_move_fix(x.gate); });
  };
  const bool fails = std::any_of(g.items.begin(), g.items.end(), [&](std::size_t i) { return fails_fixable(reports[i]); });
  if (!g.source.empty() && fails && !require.empty()) {
    const auto flag = [&](const char* name) { return html_escape(options.show_fields(field(name))); };
    details += "<p>Write a fix of every check into the source, on its grid: <code>cmr fix " +
               html_escape(shell_word(font.path)) + " " + flag("glyph") + " " + html_escape(shell_word(g.name)) +
               " " + flag("require") + " " + html_escape(require) + " " + flag("in_place") + "</code> (or <code>" +
               flag("out") + " NEW.ufo</code> for a copy; <code>" + flag("glyphs") +
               " all</code> instead of one glyph fixes every failing glyph of the font).</p>";
  }
  details += "</section>";
  return h;
}

std::string font_page_html(const std::vector<FontInfo>& fonts, const std::vector<std::vector<GlyphHtml>>& glyphs,
                           const ReportOptions& options) {
  std::string out = "<!doctype html><html><head><meta charset=\"utf-8\"><title>cmr font report</title><style>";
  out += kStyle;
  out += "</style></head><body>";
  std::string gate_names;
  for (const Gate& g : options.gates) gate_names += (gate_names.empty() ? "" : ", ") + to_string(g);
  if (options.require) gate_names += (gate_names.empty() ? "" : ", ") + to_string(*options.require);
  for (std::size_t fi = 0; fi < fonts.size(); ++fi) {
    const FontInfo& font = fonts[fi];
    int pass = 0, fail = 0;
    std::size_t contour_count = 0, contour_fail = 0;
    for (const GlyphHtml& g : glyphs[fi]) {
      contour_count += static_cast<std::size_t>(g.contours);
      contour_fail += static_cast<std::size_t>(g.contours_fail);
      ++(g.pass ? pass : fail);
    }
    out += "<h1>" + html_escape(font.family + " " + font.style) + "</h1><p>" + html_escape(font.path) + ": " +
           std::to_string(font.units_per_em) + " units per em, " + (font.cubic ? "cubic (CFF)" : "quadratic (TrueType)") +
           " outlines; <b>" +
           glyph_count_text(static_cast<int>(font.glyphs.size()), fail, static_cast<int>(contour_count),
                            static_cast<int>(contour_fail)) +
           "</b>. Gates: " +
           html_escape(gate_names.empty() ? options.show_fields("none (" + field("require") + ")") : gate_names) +
           ". Fixes are the smallest certified fix of each failing check (cmr fix: the fewest points moved the "
           "least, smooth nodes kept smooth, the fixed contour re-judged by the exact engine); each failing "
           "glyph shows its fixed outline (green) over the original (dashed).";
    if (!font.missing.empty()) out += " " + std::to_string(font.missing.size()) + " characters are not in the font.";
    out += "</p>";
    const std::string table_id = fi == 0 ? "glyphs" : "glyphs" + std::to_string(fi);
    if (fi == 0)
      out += "<p>Filter: <input id=\"q\" placeholder=\"glyph name\"> <select id=\"st\"><option value=\"\">all</option>"
             "<option>pass</option><option>fail</option></select> (click a column to sort, a thumbnail for its glyph, a glyph picture to zoom it to the window)</p>";
    out += "<table id=\"" + table_id + "\"><thead><tr><th>char</th><th>glyph</th><th>contours</th>";
    if (options.regions) out += "<th>outline and comb</th>";
    for (const Gate& g : options.gates) out += "<th>" + html_escape(to_string(g)) + "</th>";
    out += "<th>fixes</th><th>status</th></tr></thead><tbody>";
    std::string details;
    for (const GlyphHtml& g : glyphs[fi]) {
      out += g.row;
      details += g.details;
    }
    out += "</tbody></table>" + details;
  }
  out += kScript;
  out += "</body></html>\n";
  // An SVG inside HTML needs no namespace attribute (the HTML parser puts
  // it in the SVG namespace): about 35 bytes for each of a page's thousand
  // pictures.
  const std::string_view ns = " xmlns=\"http://www.w3.org/2000/svg\"";
  std::string lean;
  lean.reserve(out.size());
  for (std::size_t at = 0;;) {
    const std::size_t hit = out.find(ns, at);
    lean.append(out, at, hit == std::string::npos ? std::string::npos : hit - at);
    if (hit == std::string::npos) break;
    at = hit + ns.size();
  }
  return lean;
}

std::string font_report_html(const std::vector<FontInfo>& fonts, const std::vector<SplineReport>& reports,
                             const ReportOptions& options) {
  std::vector<std::vector<GlyphHtml>> glyphs(fonts.size());
  for (std::size_t fi = 0; fi < fonts.size(); ++fi)
    for (std::size_t gi = 0; gi < fonts[fi].glyphs.size(); ++gi)
      glyphs[fi].push_back(font_glyph_html(fonts[fi], fi, gi, reports, options));
  return font_page_html(fonts, glyphs, options);
}

}  // namespace cmr::report
