// Font import: every glyph A-Z a-z of DejaVu Sans (TrueType, quadratic) and
// Nimbus Sans (CFF, cubic) against FreeType's own FT_Outline_Decompose: the
// spline's segments and FreeType's pieces are the same curves, point by
// point along the parameter. Also the glyph spec and node names.
#include <gtest/gtest.h>

#include <algorithm>

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H

#include <filesystem>
#include <memory>
#include <set>

#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "io/font.hpp"

namespace cmr::import {
namespace {

const char* kDejaVu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
const char* kNimbus = "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf";

using Contours = std::vector<std::vector<std::vector<Vec2>>>;  // contour -> piece -> Bezier points

// FT_Outline_Decompose with shift = 1: coordinates doubled before FreeType
// takes the implied midpoints in integer arithmetic (v_control + vec) / 2, so
// the midpoints are exact; halved again here.
struct Collector {
  Contours contours;
  Vec2 cur{0.0};
  static Vec2 v(const FT_Vector* p) { return {p->x / 2.0, p->y / 2.0}; }
  void piece(std::vector<Vec2> p) {
    const bool degenerate = std::all_of(p.begin(), p.end(), [&](Vec2 q) { return q == p[0]; });
    if (!degenerate) contours.back().push_back(std::move(p));
    cur = contours.back().empty() ? cur : contours.back().back().back();
  }
};

int move_to(const FT_Vector* to, void* user) {
  auto* c = static_cast<Collector*>(user);
  c->contours.emplace_back();
  c->cur = Collector::v(to);
  return 0;
}
int line_to(const FT_Vector* to, void* user) {
  auto* c = static_cast<Collector*>(user);
  const Vec2 from = c->cur;
  c->piece({from, Collector::v(to)});
  c->cur = Collector::v(to);
  return 0;
}
int conic_to(const FT_Vector* a, const FT_Vector* to, void* user) {
  auto* c = static_cast<Collector*>(user);
  const Vec2 from = c->cur;
  c->piece({from, Collector::v(a), Collector::v(to)});
  c->cur = Collector::v(to);
  return 0;
}
int cubic_to(const FT_Vector* a, const FT_Vector* b, const FT_Vector* to, void* user) {
  auto* c = static_cast<Collector*>(user);
  const Vec2 from = c->cur;
  c->piece({from, Collector::v(a), Collector::v(b), Collector::v(to)});
  c->cur = Collector::v(to);
  return 0;
}

/// FreeType's decomposition of every glyph of `codepoints` (glyphs in order).
std::vector<Contours> freetype_pieces(const char* path, const std::vector<std::uint32_t>& codepoints) {
  FT_Library lib;
  EXPECT_EQ(FT_Init_FreeType(&lib), 0);
  FT_Face face;
  EXPECT_EQ(FT_New_Face(lib, path, 0, &face), 0);
  std::vector<Contours> out;
  const FT_Outline_Funcs funcs{move_to, line_to, conic_to, cubic_to, 1, 0};
  for (std::uint32_t cp : codepoints) {
    const FT_UInt gid = FT_Get_Char_Index(face, cp);
    EXPECT_NE(gid, 0u);
    EXPECT_EQ(FT_Load_Glyph(face, gid, FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP), 0);
    Collector c;
    EXPECT_EQ(FT_Outline_Decompose(&face->glyph->outline, &funcs, &c), 0);
    Contours kept;
    for (auto& contour : c.contours)
      if (!contour.empty()) kept.push_back(std::move(contour));
    out.push_back(std::move(kept));
  }
  FT_Done_Face(face);
  FT_Done_FreeType(lib);
  return out;
}

Vec2 bezier_at(std::vector<Vec2> p, double t) {
  for (std::size_t r = 1; r < p.size(); ++r)
    for (std::size_t i = 0; i + r < p.size(); ++i) p[i] = (1 - t) * p[i] + t * p[i + 1];
  return p[0];
}

double distance(Vec2 a, Vec2 b) { return std::sqrt(dot(a - b, a - b)); }

double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double len2 = dot(d, d);
  const double t = len2 > 0 ? std::clamp(dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
  return distance(p, a + t * d);
}

/// The largest distance between FreeType's piece k and the spline's segment
/// (k + offset) mod N, at 9 parameters each, minimised over offsets.
double round_trip_error(const BSpline& s, const std::vector<std::vector<Vec2>>& pieces) {
  const int N = s.segment_count();
  if (static_cast<int>(pieces.size()) != N) return 1e300;
  double best = 1e300;
  for (int offset = 0; offset < N; ++offset) {
    double worst = 0;
    for (int k = 0; k < N && worst < best; ++k) {
      const Segment& seg = s.segments()[(k + offset) % N];
      for (int q = 0; q <= 8; ++q) {
        const double t = q / 8.0;
        // The segment's own end: just inside it (a knot belongs to the next segment).
        const double u = q == 8 ? std::nextafter(seg.b, seg.a) : seg.a + t * (seg.b - seg.a);
        const Vec2 at = evaluate(s, u);
        double e = distance(at, bezier_at(pieces[k], t));
        // A line (FreeType's line_to) is the same set of points whatever its
        // speed: cmr puts a cubic line's inner points exactly on it, at
        // k = 21845/65536 instead of 1/3 (io/font.cpp), so inside the line
        // the distance to the line segment counts; its ends are its nodes.
        if (pieces[k].size() == 2 && q > 0 && q < 8) e = distance_to_segment(at, pieces[k][0], pieces[k][1]);
        worst = std::isfinite(e) ? std::max(worst, e) : 1e300;
      }
    }
    best = std::min(best, worst);
  }
  return best;
}

void check_font(const char* path, int degree) {
  const auto codepoints = parse_glyph_spec("A-Z,a-z");
  ASSERT_EQ(codepoints.size(), 52u);
  const Font font = read_font(path, codepoints);
  const auto reference = freetype_pieces(path, codepoints);
  ASSERT_EQ(font.glyphs.size(), reference.size());
  int contours = 0;
  for (std::size_t g = 0; g < font.glyphs.size(); ++g) {
    const Glyph& glyph = font.glyphs[g];
    ASSERT_EQ(glyph.contours.size(), reference[g].size()) << glyph.name;
    for (std::size_t c = 0; c < glyph.contours.size(); ++c) {
      const BSpline& s = glyph.contours[c].spline;
      EXPECT_TRUE(s.closed());
      EXPECT_EQ(s.degree(), degree);
      EXPECT_EQ(s.segment_count(), static_cast<int>(reference[g][c].size())) << glyph.name << " contour " << c;
      // Font units: 1e-9 of a unit is rounding only.
      EXPECT_LT(round_trip_error(s, reference[g][c]), 1e-9) << glyph.name << " contour " << c;
      EXPECT_EQ(glyph.contours[c].point_names.size(), static_cast<std::size_t>(s.unique_point_count()));
      EXPECT_EQ(glyph.contours[c].joint_names.size(), static_cast<std::size_t>(s.segment_count()));
      ++contours;
    }
  }
  EXPECT_GT(contours, 52);
}

TEST(ImportFont, DejaVuSansTrueTypeMatchesFreeTypeDecomposition) { check_font(kDejaVu, 2); }
TEST(ImportFont, NimbusSansCffMatchesFreeTypeDecomposition) { check_font(kNimbus, 3); }

// In TrueType two off-curve points in a row meet at their midpoint: a simple
// knot (C1), as a uniform quadratic B-spline has. DejaVu's "O" has such nodes.
TEST(ImportFont, TrueTypeImpliedNodesAreSimpleKnots) {
  const Font font = read_font(kDejaVu, {'O'});
  const Contour& c = font.glyphs.at(0).contours.at(0);
  int simple = 0;
  for (const Segment& seg : c.spline.segments()) simple += c.spline.multiplicity(seg.a) == 1 ? 1 : 0;
  EXPECT_GT(simple, 0);
  for (std::size_t k = 0; k < c.point_names.size(); ++k)
    EXPECT_EQ(c.point_names[k], "O/c0/p" + std::to_string(c.font_point[k])) << k;
  // An implied node is named after both off-curve points.
  bool implied = false;
  for (const std::string& n : c.joint_names) implied = implied || n.find('+') != std::string::npos;
  EXPECT_TRUE(implied);
  // The file form is readable back as the same closed spline.
  const BSpline back = spline_from_json(contour_json(c));
  EXPECT_EQ(back.points(), c.spline.points());
  EXPECT_EQ(back.knots(), c.spline.knots());
}

// Straight pieces of a CFF glyph get two added inner points at 1/3 and 2/3,
// named after the two on-curve points they join.
TEST(ImportFont, AddedLinePointsAreNamedAfterTheirNodes) {
  const Font font = read_font(kNimbus, {'I'});
  const Contour& c = font.glyphs.at(0).contours.at(0);
  int added = 0;
  for (std::size_t k = 0; k < c.point_names.size(); ++k) {
    if (c.font_point[k] >= 0) continue;
    ++added;
    const std::string& n = c.point_names[k];
    EXPECT_EQ(n.rfind("I/c0/n", 0), 0u) << n;
    EXPECT_TRUE(n.find("@1/3") != std::string::npos || n.find("@2/3") != std::string::npos) << n;
    EXPECT_EQ(n.find("-"), std::string::npos) << n;
  }
  EXPECT_EQ(added, 2 * c.spline.segment_count());  // "I" is a rectangle: four lines
  EXPECT_EQ(c.joint_names, (std::vector<std::string>{"I/c0/n0", "I/c0/n1", "I/c0/n2", "I/c0/n3"}));
  EXPECT_EQ(c.point_names.at(1), "I/c0/n0+n1@1/3");
  EXPECT_EQ(c.point_names.at(2), "I/c0/n0+n1@2/3");
  EXPECT_EQ(c.point_names.back(), "I/c0/n3+n0@2/3");  // the closing line back to the first node
}

// CFF outlines (TeX Gyre Heros, Debian fonts-texgyre): the on-curve nodes
// numbered along each contour from its first one, each handle named after
// the node it leaves (".out") or arrives at (".in"), so "n2.out" and
// "n3.in" are the handles of the piece n2-n3; the font's point index kept
// in font_point. Every name of a contour is distinct, has no '-' (the
// separator of a segment "n2-n3") and no '|' (the key separator).
// A CFF line's inner points lie exactly on it (io/font.cpp, exact_cubic_line):
// for every piece with added points ("@1/3", "@2/3") of the slanted and
// straight lines of Nimbus Sans and TeX Gyre Heros, both inner points are
// collinear with the nodes in exact integer arithmetic (the coordinates are
// dyadic with at most 16 fractional bits: scaled by 2^16 they are integers,
// their cross products fit in 128 bits), in order between them, and within
// 1e-5 of the line's length of the uniform thirds.
__extension__ using Int128 = __int128;  // GCC's, named once (-Wpedantic)

TEST(ImportFont, CffLinesAreExactlyStraight) {
  const char* heros = "/usr/share/texmf/fonts/opentype/public/tex-gyre/texgyreheros-regular.otf";
  int lines = 0, slanted = 0;
  for (const char* path : {kNimbus, heros}) {
    const Font font = read_font(path, parse_glyph_spec("A-Z,a-z,0-9"));
    for (const Glyph& g : font.glyphs)
      for (const Contour& c : g.contours) {
        const std::vector<Vec2>& p = c.spline.points();
        const std::size_t m = c.point_names.size();  // the unique points (a closed spline repeats d)
        for (std::size_t i = 0; i < m; ++i) {
          if (c.point_names[(i + 1) % m].find("@1/3") == std::string::npos) continue;
          const Vec2 a = p[i], q1 = p[(i + 1) % m], q2 = p[(i + 2) % m], b = p[(i + 3) % m];
          ASSERT_NE(c.point_names[(i + 2) % m].find("@2/3"), std::string::npos) << c.point_names[(i + 2) % m];
          auto fixed = [](double v) {
            const double scaled = std::ldexp(v, 16);
            EXPECT_EQ(scaled, std::trunc(scaled)) << v;
            return static_cast<Int128>(scaled);
          };
          auto cross = [&](Vec2 u, Vec2 v, Vec2 w) {  // (v - u) x (w - u), exactly
            return (fixed(v.x) - fixed(u.x)) * (fixed(w.y) - fixed(u.y)) - (fixed(v.y) - fixed(u.y)) * (fixed(w.x) - fixed(u.x));
          };
          EXPECT_TRUE(cross(a, q1, b) == 0 && cross(a, q2, b) == 0) << c.point_names[(i + 1) % m];
          const Vec2 d = b - a;
          const double len = std::sqrt(dot(d, d));
          EXPECT_GT(dot(q1 - a, d), 0);
          EXPECT_GT(dot(q2 - q1, d), 0);
          EXPECT_GT(dot(b - q2, d), 0);
          EXPECT_LT(distance(q1, a + d / 3.0), 1e-5 * len) << c.point_names[(i + 1) % m];
          EXPECT_LT(distance(q2, a + 2.0 * d / 3.0), 1e-5 * len) << c.point_names[(i + 2) % m];
          ++lines;
          slanted += d.x != 0 && d.y != 0 ? 1 : 0;
        }
      }
  }
  EXPECT_GT(lines, 200);
  EXPECT_GT(slanted, 40);  // "A", "V", "N", "Z", "k", "v", "w", "x", "y", "z", "4", "7" have slanted lines
}

TEST(ImportFont, CffNodesAreNumberedAlongTheContourAndHandlesNamedAfterTheirNodes) {
  const char* heros = "/usr/share/texmf/fonts/opentype/public/tex-gyre/texgyreheros-regular.otf";
  if (!std::filesystem::exists(heros)) GTEST_SKIP() << "no " << heros << " (tools/setup.sh installs fonts-texgyre)";
  const Font font = read_font(heros, parse_glyph_spec("O,e,l,H,-"));
  ASSERT_TRUE(font.cubic);
  ASSERT_EQ(font.glyphs.size(), 5u);
  for (const Glyph& g : font.glyphs)
    for (const Contour& c : g.contours) {
      const std::string prefix = g.name + "/c" + std::to_string(c.index) + "/";
      std::set<std::string> seen;
      int nodes = 0;
      for (std::size_t k = 0; k < c.point_names.size(); ++k) {
        const std::string& n = c.point_names[k];
        ASSERT_EQ(n.rfind(prefix, 0), 0u) << n;
        const std::string local = n.substr(prefix.size());
        EXPECT_TRUE(seen.insert(local).second) << n << " twice";
        EXPECT_EQ(local.find_first_of("-| "), std::string::npos) << n;
        EXPECT_EQ(local.substr(0, local.find('@')).find('/'), std::string::npos) << n;  // '/' only in "@1/3"
        if (c.node[k]) {
          EXPECT_EQ(local, "n" + std::to_string(nodes++)) << g.name << " point " << k;
        } else if (c.font_point[k] >= 0) {  // a handle: after the node before it, or before the node after it
          const bool out = c.node[k - 1];
          const int next = (nodes) % std::max(1, static_cast<int>(std::count(c.node.begin(), c.node.end(), true)));
          EXPECT_EQ(local, out ? "n" + std::to_string(nodes - 1) + ".out" : "n" + std::to_string(next) + ".in") << n;
        }
      }
      // Every segment starts at a node of a cubic contour.
      ASSERT_EQ(c.joint_names.size(), static_cast<std::size_t>(c.spline.segment_count()));
      for (std::size_t i = 0; i < c.joint_names.size(); ++i)
        EXPECT_EQ(c.joint_names[i], prefix + "n" + std::to_string(i));
    }
  // O's outer contour: four curved pieces between four nodes.
  const Contour& o = font.glyphs.at(0).contours.at(0);
  EXPECT_EQ(o.point_names, (std::vector<std::string>{"O/c0/n0", "O/c0/n0.out", "O/c0/n1.in", "O/c0/n1", "O/c0/n1.out",
                                                     "O/c0/n2.in", "O/c0/n2", "O/c0/n2.out", "O/c0/n3.in", "O/c0/n3",
                                                     "O/c0/n3.out", "O/c0/n0.in"}))
      << o.point_names.size();
  // TrueType keeps the font's point numbers (what its hinting and editors use).
  const Font tt = read_font(kDejaVu, {'l'});
  EXPECT_EQ(tt.glyphs.at(0).contours.at(0).point_names.at(0), "l/c0/p0");
}

TEST(ImportFont, GlyphSpecAndErrors) {
  EXPECT_EQ(parse_glyph_spec("A-C,x"), (std::vector<std::uint32_t>{'A', 'B', 'C', 'x'}));
  EXPECT_EQ(parse_glyph_spec("U+00E9,\xC3\xA9,U+002C"), (std::vector<std::uint32_t>{0xE9, 0x2C}));
  EXPECT_THROW(parse_glyph_spec("Z-A"), InputError);
  EXPECT_THROW(parse_glyph_spec("A,,B"), InputError);
  EXPECT_THROW(parse_glyph_spec("AB"), InputError);
  EXPECT_THROW(read_font("/nonexistent.ttf", {'A'}), InputError);
  EXPECT_THROW(read_font(__FILE__, {'A'}), InputError);
  const Font f = read_font(kDejaVu, {'A', 0x10FFFD});
  EXPECT_EQ(f.glyphs.size(), 1u);
  EXPECT_EQ(f.missing, std::vector<std::uint32_t>{0x10FFFD});
  EXPECT_TRUE(is_font_path("x/Y.OTF"));
  EXPECT_FALSE(is_font_path("x/y.json"));
}

}  // namespace
}  // namespace cmr::import
