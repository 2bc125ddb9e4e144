// SVG path data: each command in absolute and relative form against the
// curve it must draw (evaluated independently from the command's own
// numbers), reflection for S and T, closing, arcs on their ellipse (rational
// quadratics evaluated here), the number grammar and errors.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "spline/errors.hpp"
#include "io/svg.hpp"

namespace cmr::import {
namespace {

double dist(Vec2 a, Vec2 b) { return std::sqrt(dot(a - b, a - b)); }

Vec2 bezier_at(std::vector<Vec2> p, double t) {
  for (std::size_t r = 1; r < p.size(); ++r)
    for (std::size_t i = 0; i + r < p.size(); ++i) p[i] = (1 - t) * p[i] + t * p[i + 1];
  return p[0];
}

/// The spline's piece k (a chain: unit spans) at t in [0, 1].
Vec2 piece_at(const PathSpline& s, int k, double t) {
  const BSpline b = to_bspline(s);
  const Segment& seg = b.segments().at(k);
  return evaluate(b, t == 1 ? std::nextafter(seg.b, seg.a) : seg.a + t * (seg.b - seg.a));
}

/// Expects piece k of the one subpath of d to be the Bezier curve `want`.
void expect_piece(const std::string& d, int k, const std::vector<Vec2>& want) {
  const auto paths = parse_path_data(d, "t");
  ASSERT_EQ(paths.size(), 1u) << d;
  for (int q = 0; q <= 10; ++q)
    EXPECT_LT(dist(piece_at(paths[0], k, q / 10.0), bezier_at(want, q / 10.0)), 1e-12) << d << " piece " << k
                                                                                      << " t " << q / 10.0;
}

TEST(ImportSvg, LinesAbsoluteAndRelative) {
  for (const char* d : {"M1 2 L4 6", "m1 2 l3 4", "M1,2 4,6", "m1,2 3,4"}) expect_piece(d, 0, {{1, 2}, {4, 6}});
  for (const char* d : {"M1 2 H5 V7", "M1 2 h4 v5"}) {
    expect_piece(d, 0, {{1, 2}, {5, 2}});
    expect_piece(d, 1, {{5, 2}, {5, 7}});
  }
}

TEST(ImportSvg, CubicsAndSmoothReflection) {
  const std::vector<Vec2> c0{{0, 0}, {1, 2}, {3, 2}, {4, 0}};
  for (const char* d : {"M0 0 C1 2 3 2 4 0", "M0 0 c1 2 3 2 4 0"}) expect_piece(d, 0, c0);
  // S reflects the previous second control point (3,2) about (4,0): (5,-2).
  for (const char* d : {"M0 0 C1 2 3 2 4 0 S7 -2 8 0", "M0 0 c1 2 3 2 4 0 s3 -2 4 0"})
    expect_piece(d, 1, {{4, 0}, {5, -2}, {7, -2}, {8, 0}});
  // S after a non-cubic: the first control point is the current point.
  expect_piece("M0 0 L1 0 S2 1 3 0", 1, {{1, 0}, {1, 0}, {2, 1}, {3, 0}});
}

TEST(ImportSvg, QuadraticsAndSmoothReflection) {
  for (const char* d : {"M0 0 Q1 2 2 0", "M0 0 q1 2 2 0"}) expect_piece(d, 0, {{0, 0}, {1, 2}, {2, 0}});
  // T reflects (1,2) about (2,0): (3,-2).
  for (const char* d : {"M0 0 Q1 2 2 0 T4 0", "M0 0 q1 2 2 0 t2 0"}) expect_piece(d, 1, {{2, 0}, {3, -2}, {4, 0}});
  expect_piece("M0 0 L1 0 T3 0", 1, {{1, 0}, {1, 0}, {3, 0}});
}

TEST(ImportSvg, MixedDegreesAreElevatedExactly) {
  // A quadratic and a line in a cubic subpath: same curves at degree 3.
  const auto paths = parse_path_data("M0 0 Q1 2 2 0 L3 1 C4 1 5 0 6 0", "t");
  ASSERT_EQ(paths.size(), 1u);
  EXPECT_EQ(paths[0].degree, 3);
  EXPECT_FALSE(paths[0].rational());
  for (int q = 0; q <= 10; ++q) {
    EXPECT_LT(dist(piece_at(paths[0], 0, q / 10.0), bezier_at({{0, 0}, {1, 2}, {2, 0}}, q / 10.0)), 1e-12);
    EXPECT_LT(dist(piece_at(paths[0], 1, q / 10.0), bezier_at({{2, 0}, {3, 1}}, q / 10.0)), 1e-12);
  }
}

TEST(ImportSvg, ClosePathMakesAClosedSpline) {
  for (const char* d : {"M0 0 L4 0 L4 3 Z", "m0 0 l4 0 l0 3 z"}) {
    const auto paths = parse_path_data(d, "t");
    ASSERT_EQ(paths.size(), 1u);
    EXPECT_TRUE(paths[0].closed);
    const auto b = to_bspline(paths[0]);
    ASSERT_TRUE(b.closed());
    EXPECT_EQ(b.segment_count(), 3);  // the closing line back to (0,0) included
    EXPECT_LT(dist(piece_at(paths[0], 2, 0.5), {2, 1.5}), 1e-12);
  }
  // After Z the current point is the subpath's start; a relative move is from there.
  const auto two = parse_path_data("M1 1 l2 0 l0 2 z m1 0 l1 1", "t");
  ASSERT_EQ(two.size(), 2u);
  EXPECT_FALSE(two[1].closed);
  EXPECT_LT(dist(two[1].points.front(), {2, 1}), 1e-15);
  EXPECT_EQ(two[1].name, "t/s1");
}

// A point of a rational quadratic arc piece (Piece weights) lies on the ellipse
// when rotating back by phi and scaling by the radii gives the unit circle.
TEST(ImportSvg, ArcsAreRationalQuadraticsOnTheEllipse) {
  const Vec2 c(10, 5);
  const double rx = 4, ry = 2, phi = 30 * std::numbers::pi / 180;
  auto E = [&](double th) {
    const double x = rx * std::cos(th), y = ry * std::sin(th);
    return c + Vec2(std::cos(phi) * x - std::sin(phi) * y, std::sin(phi) * x + std::cos(phi) * y);
  };
  auto on_ellipse = [&](Vec2 p) {
    const Vec2 q = p - c;
    const double x = std::cos(phi) * q.x + std::sin(phi) * q.y, y = -std::sin(phi) * q.x + std::cos(phi) * q.y;
    return x * x / (rx * rx) + y * y / (ry * ry) - 1;
  };
  const double a0 = 10 * std::numbers::pi / 180, a1 = 250 * std::numbers::pi / 180;  // 240 degrees, positive
  const Vec2 p0 = E(a0), p1 = E(a1);
  char abs_d[256], rel_d[256];
  std::snprintf(abs_d, sizeof abs_d, "M%.17g %.17g A4 2 30 1 1 %.17g %.17g", p0.x, p0.y, p1.x, p1.y);
  std::snprintf(rel_d, sizeof rel_d, "M%.17g %.17g a4 2 30 1 1 %.17g %.17g", p0.x, p0.y, p1.x - p0.x, p1.y - p0.y);
  for (const char* d : {abs_d, rel_d}) {
    const auto paths = parse_path_data(d, "t");
    ASSERT_EQ(paths.size(), 1u);
    const PathSpline& s = paths[0];
    ASSERT_TRUE(s.rational());
    ASSERT_EQ(s.degree, 2);
    const BSpline b = to_bspline(s);
    ASSERT_TRUE(b.is_rational());
    for (const Segment& seg : b.segments())  // the spline evaluates on the ellipse too
      EXPECT_LT(std::abs(on_ellipse(evaluate(b, 0.5 * (seg.a + seg.b)))), 1e-12);
    const int pieces = (static_cast<int>(s.points.size()) - 1) / 2;
    EXPECT_EQ(pieces, 3);  // 240 degrees in pieces of at most 90
    double worst = 0, last_angle = a0;
    for (int k = 0; k < pieces; ++k) {
      const std::vector<Vec2> P(s.points.begin() + 2 * k, s.points.begin() + 2 * k + 3);
      const std::vector<double> W(s.weights.begin() + 2 * k, s.weights.begin() + 2 * k + 3);
      for (int q = 0; q <= 20; ++q) {
        const Vec2 p = rational_bezier_point(P, W, q / 20.0);
        worst = std::max(worst, std::abs(on_ellipse(p)));
        // The eccentric angle moves forward (sweep flag 1: increasing angle).
        const Vec2 r = p - c;
        const double x = std::cos(phi) * r.x + std::sin(phi) * r.y, y = -std::sin(phi) * r.x + std::cos(phi) * r.y;
        double ang = std::atan2(y / ry, x / rx);
        while (ang < last_angle - 1e-9) ang += 2 * std::numbers::pi;
        EXPECT_LE(ang, last_angle + std::numbers::pi / 2) << "piece " << k << " t " << q / 20.0;
        last_angle = ang;
      }
    }
    EXPECT_LT(worst, 1e-12) << d;
    EXPECT_NEAR(last_angle, a1, 1e-9);
    EXPECT_LT(dist(s.points.back(), p1), 1e-12);
    const nlohmann::json j = path_json(s);
    EXPECT_EQ(j["weights"].size(), s.points.size());
  }
  // Large-arc 0 with the same ends: the other way, the short 120-degree arc.
  char small[256];
  std::snprintf(small, sizeof small, "M%.17g %.17g A4 2 30 0 0 %.17g %.17g", p0.x, p0.y, p1.x, p1.y);
  const auto s = parse_path_data(small, "t").at(0);
  EXPECT_EQ((s.points.size() - 1) / 2, 2u);
  EXPECT_LT(std::abs(on_ellipse(rational_bezier_point({s.points[0], s.points[1], s.points[2]},
                                                     {s.weights[0], s.weights[1], s.weights[2]}, 0.5))),
            1e-12);
}

TEST(ImportSvg, DegenerateArcsFollowTheSpec) {
  // Zero radius: a straight line; equal ends: nothing (no subpath left).
  expect_piece("M0 0 A0 3 0 0 1 4 0", 0, {{0, 0}, {4, 0}});
  EXPECT_TRUE(parse_path_data("M1 1 A3 3 0 0 1 1 1", "t").empty());
  // Radii too small are scaled up (F.6.6): a half circle through both ends.
  const auto s = parse_path_data("M0 0 A1 1 0 0 1 4 0", "t").at(0);
  for (std::size_t k = 0; k + 2 < s.points.size(); k += 2) {
    const Vec2 p = rational_bezier_point({s.points[k], s.points[k + 1], s.points[k + 2]},
                                         {s.weights[k], s.weights[k + 1], s.weights[k + 2]}, 0.3);
    EXPECT_NEAR(dist(p, {2, 0}), 2.0, 1e-12);
  }
}

TEST(ImportSvg, NumberGrammarAndErrors) {
  // Signs and dots separate numbers; exponents; arc flags without separators.
  expect_piece("M.5.5L-1-2", 0, {{0.5, 0.5}, {-1, -2}});
  expect_piece("M1e1,+2E-1 l1e0-1", 0, {{10, 0.2}, {11, -0.8}});
  EXPECT_EQ(parse_path_data("M0 0a1 1 0 104 0", "t").size(), 1u);
  auto message = [](const std::string& d) {
    try {
      (void)parse_path_data(d, "t");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("L1 2"), "d[0]: path data must start with M or m");
  EXPECT_EQ(message("1 2"), "d[0]: path data must start with M or m");
  EXPECT_EQ(message("M1 2 L3"), "d[7]: expected a number");
  EXPECT_EQ(message("M1 2 X3 4"), "d[5]: unknown command 'X'");
  EXPECT_EQ(message("M0 0 A1 1 0 2 0 3 3"), "d[12]: expected an arc flag 0 or 1");
  EXPECT_EQ(message("M0 0 L1 1 Z 3"), "d[12]: numbers after Z");
}

TEST(ImportSvg, ReadsEveryPathOfAFile) {
  const auto path = std::filesystem::temp_directory_path() / ("cmr_import_svg_" + std::to_string(::getpid()) + ".svg");
  {
    std::ofstream out(path);
    out << "<svg xmlns='http://www.w3.org/2000/svg'><path id=\"bowl\" d=\"M0 0 Q5 5 10 0 Z\"/>"
           "<rect/><path fill='none' d='M0 0 C1 1 2 1 3 0 M5 5 L6 6'/></svg>";
  }
  const auto paths = read_svg(path);
  ASSERT_EQ(paths.size(), 3u);
  const std::string stem = path.stem().string();
  EXPECT_EQ(paths[0].name, stem + "/bowl/s0");
  EXPECT_TRUE(paths[0].closed);
  EXPECT_EQ(paths[1].name, stem + "/path1/s0");
  EXPECT_EQ(paths[2].name, stem + "/path1/s1");
  std::ofstream(path) << "<svg><path d='M0 0 L'/></svg>";
  try {
    (void)read_svg(path);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(": path 0, d[6]: expected a number"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace cmr::import

namespace cmr::import {
namespace {

std::string svg_error(const std::string& text, const SvgOptions& o = {}) {
  try {
    (void)read_svg_text(text, "t.svg", "t", o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// Issue 26 D1: each number finite, the computed coordinates not.
TEST(ImportSvgDocument, NonFiniteCoordinatesNameThePathAndOffset) {
  EXPECT_EQ(svg_error("<svg><path d='M0 0'/><path d=\"M0 0 A 5 50 0 1 1 10 -1e308\"/></svg>"),
            "t.svg: path 1, d[5]: the command's coordinates are not finite (they overflow)");
  EXPECT_EQ(svg_error("<svg><path d='M 1e308 0 l 1e308 0 l 0 1'/></svg>"),
            "t.svg: path 0, d[10]: the command's coordinates are not finite (they overflow)");
  EXPECT_EQ(svg_error("<svg><path d='M 1e308 0 h 1e308'/></svg>"),
            "t.svg: path 0, d[10]: the command's coordinates are not finite (they overflow)");
  // A reflected control point (2 P - C) overflows.
  EXPECT_EQ(svg_error("<svg><path d='M 0 0 C 1e308 0 0 0 -1e308 0 S 0 0 0 0'/></svg>"),
            "t.svg: path 0, d[29]: the command's coordinates are not finite (they overflow)");
  // A transform that overflows finite path data.
  EXPECT_EQ(svg_error("<svg><g transform='scale(1e300)'><path d='M 1e300 0 L 0 1'/></g></svg>"),
            "t.svg: path 0: a coordinate is not finite after the transform");
}

// Issue 26 D4: a long path (was std::regex recursion, SIGSEGV) and deep nesting.
TEST(ImportSvgDocument, LongPathsAndDeepNestingAreLinear) {
  std::string d = "M0 0";
  for (int k = 0; k < 20000; ++k) d += " L" + std::to_string(k % 7) + " " + std::to_string(k % 5);
  const auto paths = read_svg_text("<svg><path d='" + d + "'/></svg>", "t.svg", "t");
  ASSERT_EQ(paths.size(), 1u);
  EXPECT_EQ(paths[0].points.size(), 2u * 20000 + 1);
  std::string deep;
  for (int k = 0; k < 100000; ++k) deep += "<g transform='translate(1)'>";
  deep += "<path d='M0 0 L1 1'/>";
  for (int k = 0; k < 100000; ++k) deep += "</g>";
  const auto nested = read_svg_text("<svg>" + deep + "</svg>", "t.svg", "t");
  ASSERT_EQ(nested.size(), 1u);
  EXPECT_EQ(nested[0].points[0], Vec2(100000, 0));
}

// XML as XML defines it: comments, CDATA, processing instructions and the
// DOCTYPE are no elements; entities and attribute normalisation.
TEST(ImportSvgDocument, CommentsCdataEntitiesAndAttributes) {
  const auto paths = read_svg_text(
      "<?xml version='1.0'?><!DOCTYPE svg><svg xmlns:svg='http://www.w3.org/2000/svg'>"
      "<!-- <path id='commented' d='M0 0 L1 1'/> -->"
      "<text><![CDATA[<path id='cdata' d='M0 0 L1 1'/>]]></text>"
      "<?pi <path d='M0 0 L1 1'/>?>"
      "<path id='a&amp;b' d='M0&#x20;0&#10;L&#x33; 4'/><svg:path id='ns' d='M0 0 L5 0'/></svg>",
      "t.svg", "t", {.flip_y = false});
  ASSERT_EQ(paths.size(), 2u);
  EXPECT_EQ(paths[0].name, "t/a&b/s0");
  EXPECT_EQ(paths[0].points.back(), Vec2(3, 4));
  EXPECT_EQ(paths[1].name, "t/ns/s0");
  // Entities a DOCTYPE declares are not expanded, internal or external.
  EXPECT_EQ(svg_error("<!DOCTYPE svg [<!ENTITY e 'L1 1'>]><svg><path d='M0 0 &e;'/></svg>"),
            "t.svg: path 0, d[5]: expected a number");
  EXPECT_EQ(svg_error("<!DOCTYPE svg [<!ENTITY x SYSTEM 'file:///etc/passwd'>]><svg><path d='&x;'/></svg>"),
            "t.svg: path 0, d[0]: path data must start with M or m");
  EXPECT_EQ(svg_error("<svg><!-- <path d='M0 0 L1 1'/> --></svg>"), "t.svg: no <path> with curve data");
  // An id that is not UTF-8 (found by fuzz_svg_document: the JSON writer threw) names the path by number.
  const auto bad_id = read_svg_text("<svg><path id='a\xff\xff' d='M0 0 L1 1'/></svg>", "t.svg", "t");
  EXPECT_EQ(bad_id.at(0).name, "t/path0/s0");
  EXPECT_NO_THROW((void)path_json(bad_id.at(0)).dump());
  EXPECT_EQ(svg_error("<svg><path d='M0 0 L1 1'></svg>").substr(0, 35), "t.svg: not well-formed XML at byte ");
}

// Issue 20.6: y-up by default, SVG coordinates on request.
TEST(ImportSvgDocument, FlippedToYUpByDefault) {
  const std::string doc = "<svg><path d='M1 2 Q3 4 5 6 A1 1 0 0 1 7 6'/></svg>";
  const auto up = read_svg_text(doc, "t.svg", "t");
  const auto down = read_svg_text(doc, "t.svg", "t", {.flip_y = false});
  ASSERT_EQ(up.size(), 1u);
  ASSERT_EQ(up[0].points.size(), down[0].points.size());
  EXPECT_EQ(down[0].points[0], Vec2(1, 2));
  for (std::size_t k = 0; k < up[0].points.size(); ++k)
    EXPECT_EQ(up[0].points[k], Vec2(down[0].points[k].x, -down[0].points[k].y)) << "point " << k;
  EXPECT_EQ(up[0].weights, down[0].weights);
}

// Issue 20.6: transforms on paths and nested groups, each kind against its
// SVG 1.1 §7.6 matrix; the list's first transform is the outermost.
TEST(ImportSvgDocument, TransformsOnPathsAndNestedGroups) {
  auto first_points = [](const std::string& body) {
    const auto p = read_svg_text("<svg>" + body + "</svg>", "t.svg", "t", {.flip_y = false});
    return std::pair(p.at(0).points.front(), p.at(0).points.back());
  };
  auto near = [](Vec2 a, Vec2 b) { return std::abs(a.x - b.x) < 1e-12 && std::abs(a.y - b.y) < 1e-12; };
  const std::string line = "d='M1 2 L3 5'";
  EXPECT_EQ(first_points("<g transform='translate(10,5)'><path " + line + "/></g>"), std::pair(Vec2(11, 7), Vec2(13, 10)));
  EXPECT_EQ(first_points("<g transform='translate(10)'><path " + line + "/></g>").first, Vec2(11, 2));
  EXPECT_EQ(first_points("<g transform='scale(2)'><g transform='scale(1 3)'><path " + line + "/></g></g>").second,
            Vec2(6, 30));
  EXPECT_EQ(first_points("<g transform='translate(1,1) scale(2)'><path " + line + "/></g>").first, Vec2(3, 5));
  EXPECT_EQ(first_points("<g transform='scale(2)'><path transform='translate(1,1)' " + line + "/></g>").first,
            Vec2(4, 6));
  EXPECT_TRUE(near(first_points("<path transform='rotate(90)' " + line + "/>").first, Vec2(-2, 1)));
  EXPECT_TRUE(near(first_points("<path transform='rotate(90 1 2)' " + line + "/>").second, Vec2(-2, 4)));
  EXPECT_TRUE(near(first_points("<path transform='skewX(45)' " + line + "/>").first, Vec2(3, 2)));
  EXPECT_TRUE(near(first_points("<path transform='skewY(45)' " + line + "/>").first, Vec2(1, 3)));
  EXPECT_EQ(first_points("<path transform='matrix(1 2 3 4 5 6)' " + line + "/>").first, Vec2(12, 16));
  // Siblings do not inherit each other's transforms.
  const auto two = read_svg_text("<svg><g transform='translate(5 0)'><path d='M0 0 L1 0'/></g><path d='M0 0 L1 0'/></svg>",
                                 "t.svg", "t", {.flip_y = false});
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].points[0], Vec2(5, 0));
  EXPECT_EQ(two[1].points[0], Vec2(0, 0));
  // Flip after the transforms: a translated drawing flipped as a whole.
  EXPECT_EQ(read_svg_text("<svg><g transform='translate(0 10)'><path " + line + "/></g></svg>", "t.svg", "t")[0].points[0],
            Vec2(1, -12));
}

TEST(ImportSvgDocument, TransformErrors) {
  auto message = [](const std::string& t) {
    try {
      (void)parse_transform(t);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("translate(1,2) scale(2)"), "no error");
  EXPECT_EQ(message("  "), "no error");
  EXPECT_EQ(message("shear(1)"), "transform[0]: unknown transform 'shear'");
  EXPECT_EQ(message("rotate(1 2)"), "transform[6]: rotate takes 1 or 3 numbers, not 2");
  EXPECT_EQ(message("matrix(1 2 3)"), "transform[6]: matrix takes 6 numbers, not 3");
  EXPECT_EQ(message("scale 2"), "transform[6]: expected '(' after scale");
  EXPECT_EQ(message("scale(2"), "transform[7]: expected ')' after scale's numbers");
  EXPECT_EQ(message("scale(1e999)"), "transform[6]: '1e999' is not a finite number");
  EXPECT_EQ(svg_error("<svg><g transform='scale(x)'><path d='M0 0 L1 1'/></g></svg>"),
            "t.svg: <g> (byte 6), transform[6]: expected a number");
}

}  // namespace
}  // namespace cmr::import
