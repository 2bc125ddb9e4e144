// The 3D export of a space region (draw/space_mesh.hpp): the tube lies at its
// radius from the curve, normal to it; the patch lies in the plane and covers
// the view exactly; merging; the files parse back with OpenMesh's readers.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // in OpenMesh's headers (see draw/mesh.hpp)
#include <OpenMesh/Core/IO/MeshIO.hh>
#pragma GCC diagnostic pop

#include "draw/space_mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <glm/geometric.hpp>

#include "spline/errors.hpp"

namespace cmr::mesh {
namespace {

namespace fs = std::filesystem;

SpaceSpline helix(bool closed) {
  std::vector<Vec3> p;
  for (int i = 0; i < 7; ++i) p.push_back({3 * std::cos(0.9 * i), 3 * std::sin(0.9 * i), 0.7 * i + (i % 2) * 0.3});
  if (closed) return SpaceSpline::make_closed(3, {0, 1, 2, 3, 4, 5, 6, 7}, p, "loop");
  return SpaceSpline::make(3, {0, 0, 0, 1, 2, 2.5, 4, 4, 4}, p, "helix");
}

// Distance from p to the curve, by dense sampling refined with a local search.
double distance_to_curve(const SpaceSpline& s, const Vec3& p, double* at = nullptr) {
  const int n = 4000;
  double best = 1e300, bt = 0;
  for (int i = 0; i <= n; ++i) {
    const double t = s.domain_begin() + (s.domain_end() - s.domain_begin()) * i / n;
    const double d = glm::length(evaluate(s, t) - p);
    if (d < best) best = d, bt = t;
  }
  double h = (s.domain_end() - s.domain_begin()) / n;
  for (int it = 0; it < 60; ++it) {  // golden-free local refinement: shrink around the best
    for (const double t : {bt - h, bt + h}) {
      const double tc = std::clamp(t, s.domain_begin(), s.domain_end());
      const double d = glm::length(evaluate(s, tc) - p);
      if (d < best) best = d, bt = tc;
    }
    h *= 0.7;
  }
  if (at) *at = bt;
  return best;
}

Mesh read_back(const std::string& text, const std::string& ext) {
  const fs::path p = fs::temp_directory_path() / ("cmr_space_mesh_test_" + std::to_string(::getpid()) + ext);
  std::ofstream(p) << text;
  Mesh m;
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexColor;
  EXPECT_TRUE(OpenMesh::IO::read_mesh(m, p.string(), opt)) << ext;
  fs::remove(p);
  return m;
}

TEST(SpaceMesh, TubeVerticesLieAtTheRadiusNormalToTheCurve) {
  for (const bool closed : {false, true}) {
    const SpaceSpline s = helix(closed);
    TubeOptions o;
    o.radius = 0.05;
    const Mesh m = curve_tube(s, o);
    const std::size_t samples = tube_parameters(s, o.max_turn).size() - (closed ? 1 : 0);
    EXPECT_EQ(m.n_vertices(), samples * 16 + (closed ? 0 : 2)) << closed;
    EXPECT_EQ(m.n_faces(), (samples - (closed ? 0 : 1)) * 32 + (closed ? 0 : 32)) << closed;
    EXPECT_TRUE(is_closed(m)) << closed;  // a closed surface: end caps, or the loop joined
    EXPECT_GT(mesh_volume(m), 0) << closed;  // outward normals
    int on_curve = 0;
    for (const auto v : m.vertices()) {
      const Vec3 p(m.point(v)[0], m.point(v)[1], m.point(v)[2]);
      double t = 0;
      const double d = distance_to_curve(s, p, &t);
      if (d < 1e-9) {
        ++on_curve;  // an end cap's centre
        continue;
      }
      ASSERT_NEAR(d, o.radius, 1e-6 * o.radius) << closed << " vertex " << v.idx();
      // Normal to the tangent there.
      const Vec3 tan = glm::normalize(derivative(s, t, 1));
      ASSERT_NEAR(glm::dot(glm::normalize(p - evaluate(s, t)), tan), 0, 1e-5) << v.idx();
    }
    EXPECT_EQ(on_curve, closed ? 0 : 2);
  }
}

TEST(SpaceMesh, AdaptiveSamplesFollowTheTurn) {
  const SpaceSpline s = helix(false);
  const auto coarse = tube_parameters(s, 0.5), fine = tube_parameters(s, 0.05);
  EXPECT_GT(fine.size(), 4 * coarse.size() / 2);
  EXPECT_EQ(fine.front(), s.domain_begin());
  EXPECT_EQ(fine.back(), s.domain_end());
  for (std::size_t k = 1; k < fine.size(); ++k) EXPECT_LT(fine[k - 1], fine[k]);
  // A straight piece needs no more than the halving of each segment.
  const SpaceSpline line = SpaceSpline::make(2, {0, 0, 1, 1}, {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}});
  EXPECT_EQ(tube_parameters(line, 0.05).size(), 3u);
  TubeOptions bad;
  bad.radius = -1;
  EXPECT_THROW(curve_tube(line, bad), InputError);
}

RegionResult map(int w, int h, const std::vector<Direction>& labels, View view) {
  RegionResult r;
  r.width = w, r.height = h, r.view = view;
  r.labels = labels;
  r.depth.assign(labels.size(), 0);
  return r;
}

TEST(SpaceMesh, PatchLiesInThePlaneCoversTheViewAndMerges) {
  const SpacePlane plane{{1, 2, 3}, {1, 1, 0}, {0, 0.5, 2}};
  const View view{-1, -2, 3, 1};
  const Vec3 normal = glm::normalize(glm::cross(plane.u, plane.v));
  const double scale = glm::length(glm::cross(plane.u, plane.v));
  // One label: one rectangle.
  const Mesh one = plane_patch(map(8, 5, std::vector<Direction>(40, Direction::increasing), view), plane);
  EXPECT_EQ(one.n_faces(), 2u);
  EXPECT_NEAR(mesh_area(one), 4 * 3 * scale, 1e-12);
  // A checkerboard: nothing merges; random labels: fewer, and the same area.
  std::vector<Direction> check, random;
  std::mt19937 rng(5);
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 9; ++i) {
      check.push_back((i + j) % 2 ? Direction::increasing : Direction::none);
      random.push_back(rng() % 5 == 0 ? Direction::decreasing : Direction::none);
    }
  EXPECT_EQ(plane_patch(map(9, 6, check, view), plane).n_faces(), 2u * 54);
  const Mesh r = plane_patch(map(9, 6, random, view), plane);
  EXPECT_LT(r.n_faces(), 2u * 54);
  EXPECT_NEAR(mesh_area(r), 4 * 3 * scale, 1e-12);
  for (const auto v : r.vertices()) {
    const Vec3 p(r.point(v)[0], r.point(v)[1], r.point(v)[2]);
    EXPECT_NEAR(glm::dot(p - plane.origin, normal), 0, 1e-12);
    // Its plane coordinates (a, b) are inside the view: the Gram system of U, V.
    const Vec3 q = p - plane.origin;
    const double uu = glm::dot(plane.u, plane.u), uv = glm::dot(plane.u, plane.v), vv = glm::dot(plane.v, plane.v);
    const double qu = glm::dot(q, plane.u), qv = glm::dot(q, plane.v), det = uu * vv - uv * uv;
    const double a = (qu * vv - qv * uv) / det, b = (qv * uu - qu * uv) / det;
    EXPECT_TRUE(a > view.x0 - 1e-12 && a < view.x1 + 1e-12 && b > view.y0 - 1e-12 && b < view.y1 + 1e-12) << a << " " << b;
    const auto lbl = vertex_label(r, v);
    EXPECT_TRUE(lbl == static_cast<std::uint8_t>(Direction::none) || lbl == static_cast<std::uint8_t>(Direction::decreasing));
  }
  // Each face's label is the pixel's: the area of the decreasing faces is
  // the number of decreasing pixels times a pixel's area.
  int dec = 0;
  for (const Direction d : random) dec += d == Direction::decreasing;
  double dec_area = 0;
  for (const auto f : r.faces()) {
    auto it = r.cfv_iter(f);
    const auto a = *it++, b = *it++, c = *it;
    if (vertex_label(r, a) != static_cast<std::uint8_t>(Direction::decreasing)) continue;
    dec_area += 0.5 * ((r.point(b) - r.point(a)) % (r.point(c) - r.point(a))).norm();
  }
  EXPECT_NEAR(dec_area, dec * (4.0 / 9) * (3.0 / 6) * scale, 1e-12);
}

TEST(SpaceMesh, FilesParseBackWithOpenMesh) {
  const SpaceSpline s = helix(false);
  TubeOptions o;
  o.radius = 0.1;
  Mesh m = plane_patch(map(4, 4, std::vector<Direction>(16, Direction::none), {0, 0, 1, 1}), {});
  append(m, curve_tube(s, o));
  for (const std::string ext : {".obj", ".ply"}) {
    const Mesh back = read_back(mesh_file("x" + ext, m), ext);
    EXPECT_EQ(back.n_vertices(), m.n_vertices()) << ext;
    EXPECT_EQ(back.n_faces(), m.n_faces()) << ext;
    for (const auto v : m.vertices())
      ASSERT_LT((back.point(OpenMesh::VertexHandle(v.idx())) - m.point(v)).norm(), 1e-5) << ext << " " << v.idx();
  }
  EXPECT_THROW(check_mesh_file_name("x.stl"), InputError);
  EXPECT_NO_THROW(check_mesh_file_name("X.PLY"));
}

}  // namespace
}  // namespace cmr::mesh
