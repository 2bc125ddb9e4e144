// OpenMesh's own readers (an independent parser) must be included before the
// mesh type.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // in OpenMesh's headers (see draw/mesh.hpp)
#include <OpenMesh/Core/IO/MeshIO.hh>
#pragma GCC diagnostic pop

#include "draw/mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include "spline/errors.hpp"

namespace cmr::mesh {
namespace {

namespace fs = std::filesystem;

int boundary_loops(const Mesh& m) {
  std::set<int> seen;
  int loops = 0;
  for (const auto h : m.halfedges()) {
    if (!m.is_boundary(h) || seen.count(h.idx())) continue;
    ++loops;
    for (auto g = h; !seen.count(g.idx()); g = m.next_halfedge_handle(g)) seen.insert(g.idx());
  }
  return loops;
}

// The "v" lines of an OBJ text, parsed with strtod (17 digits read back exactly).
std::vector<Mesh::Point> obj_points(const std::string& text) {
  std::vector<Mesh::Point> points;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    char* end = nullptr;
    const double x = std::strtod(line.c_str() + 2, &end), y = std::strtod(end, &end), z = std::strtod(end, &end);
    points.emplace_back(x, y, z);
  }
  return points;
}

Mesh read_back(const std::string& text, const std::string& ext) {
  const fs::path p = fs::temp_directory_path() / ("cmr_mesh_test_" + std::to_string(::getpid()) + ext);
  std::ofstream(p) << text;
  Mesh m;
  EXPECT_TRUE(OpenMesh::IO::read_mesh(m, p.string())) << ext;
  fs::remove(p);
  return m;
}

// One "in" voxel of unit spacing: the surface is the link of the sample in the
// Kuhn triangulation scaled by 1/2. The sample has 14 neighbours (6 along the
// axes, 6 face diagonals and 2 body diagonals along the main diagonal) and
// lies in 24 tetrahedra; in each the surface is the triangle on the midpoints
// of its three edges from the sample, 1/4 of the opposite face. Opposite faces:
// in the 2 cubes where the sample is an end of the main diagonal (6
// tetrahedra each) right triangles with legs 1, 1 (area 1/2); in the other 6
// cubes (2 tetrahedra each) triangles spanned by (1,1,0) and (1,1,1), area
// |(1,-1,0)| / 2 = sqrt(2)/2. Area (12 / 2 + 12 sqrt(2) / 2) / 4; volume
// 24 * (1/6) / 8 (the star, scaled by 1/2).
TEST(Mesh, OneVoxelTubeIsTheScaledLinkInClosedForm) {
  VoxelStack s;
  s.width = s.height = 3;
  s.view = View{0, 0, 3, 3};
  s.knots = {0, 1, 2};
  s.in.assign(27, false);
  s.in[13] = true;  // the centre
  const Mesh m = tube_mesh(s);
  EXPECT_EQ(m.n_vertices(), 14u);
  EXPECT_EQ(m.n_faces(), 24u);
  EXPECT_TRUE(is_closed(m));
  EXPECT_NEAR(mesh_area(m), 1.5 * (1 + std::numbers::sqrt2), 1e-12);
  EXPECT_NEAR(mesh_volume(m), 0.5, 1e-12);  // positive: normals point out
}

// A ball of radius R voxels: closed, genus 0 (Euler characteristic 2), area
// and volume near the sphere's (marching tetrahedra with midpoints cuts
// corners by about half a voxel: the volume within 15% at R = 6).
TEST(Mesh, BallTubeIsAClosedSphere) {
  const int n = 17;
  const double R = 6, c = 8;
  VoxelStack s;
  s.width = s.height = n;
  s.view = View{0, 0, n, n};
  for (int k = 0; k < n; ++k) s.knots.push_back(k + 0.5);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) s.in.push_back(std::hypot(i - c, j - c, k - c) < R);
  const Mesh m = tube_mesh(s);
  EXPECT_TRUE(is_closed(m));
  EXPECT_EQ(static_cast<long>(m.n_vertices()) - static_cast<long>(m.n_edges()) + static_cast<long>(m.n_faces()), 2);
  // The surface follows the voxels' steps (cut by the tetrahedra's diagonals),
  // so it is larger than the sphere's, and smaller than the 1.5 times of a
  // staircase of axis-aligned voxel faces.
  const double sphere = 4 * std::numbers::pi * R * R;
  EXPECT_GT(mesh_area(m), sphere);
  EXPECT_LT(mesh_area(m), 1.5 * sphere);
  EXPECT_NEAR(mesh_volume(m), 4.0 / 3 * std::numbers::pi * R * R * R, 0.15 * 4.0 / 3 * std::numbers::pi * R * R * R);
  // Voxels touching the stack's ends are closed by the padding too.
  VoxelStack full = s;
  full.in.assign(full.in.size(), true);
  const Mesh box = tube_mesh(full);
  EXPECT_TRUE(is_closed(box));
  EXPECT_NEAR(mesh_volume(box), n * n * n, 0.1 * n * n * n);
}

TEST(Mesh, InconsistentStackIsAnInputError) {
  VoxelStack s;
  s.width = s.height = 2;
  s.knots = {0, 1};
  s.in.assign(7, true);
  EXPECT_THROW(tube_mesh(s), InputError);
  s.in.assign(8, true);
  s.knots = {1, 1};
  EXPECT_THROW(tube_mesh(s), InputError);
}

// The regions of the quadratic Bezier's middle point (two disks, see
// tests/region/contour_test.cpp): the mesh's area per label is the contour
// area, its boundary loops are the outlines, and the OBJ and PLY files read
// back with OpenMesh's readers give the same vertices and area.
TEST(Mesh, RegionMeshMatchesContoursAndReadsBack) {
  const BSpline spline = BSpline::bezier({{0, 0}, {2, 1}, {4, 0}});
  RegionRequest rq;
  rq.point = 1;
  rq.width = 60;
  rq.height = 40;
  rq.view = View{-0.53, -1.47, 4.61, 1.71};
  const RegionProblem problem = RegionProblem::make(spline, rq);
  CpuRegionBackend cpu(2);
  const RegionContours rc = region_contours(problem, cpu.render(problem));
  const Mesh m = region_mesh(rc);
  double area = 0;
  std::size_t vertices = 0, outlines = 0;
  for (const LabelContours& lc : rc.labels) area += lc.area, vertices += lc.vertices.size(), outlines += lc.outlines.size();
  EXPECT_EQ(m.n_vertices(), vertices);
  EXPECT_NEAR(mesh_area(m), area, 1e-9 * area);
  EXPECT_EQ(boundary_loops(m), static_cast<int>(outlines));
  std::set<int> labels;
  for (const auto v : m.vertices()) labels.insert(vertex_label(m, v));
  EXPECT_EQ(labels.size(), rc.labels.size());

  // OpenMesh's readers keep floats: the same mesh to float precision.
  const Mesh obj = read_back(obj_text(m), ".obj");
  EXPECT_EQ(obj.n_vertices(), m.n_vertices());
  EXPECT_EQ(obj.n_faces(), m.n_faces());
  EXPECT_NEAR(mesh_area(obj), mesh_area(m), 1e-5 * area);
  const Mesh ply = read_back(ply_text(m), ".ply");
  EXPECT_EQ(ply.n_vertices(), m.n_vertices());
  EXPECT_EQ(ply.n_faces(), m.n_faces());
  EXPECT_NEAR(mesh_area(ply), mesh_area(m), 1e-5 * area);
  // The text itself holds every double exactly.
  const std::vector<Mesh::Point> exact = obj_points(obj_text(m));
  ASSERT_EQ(exact.size(), m.n_vertices());
  for (const auto v : m.vertices()) EXPECT_EQ(exact[v.idx()], m.point(v));

  const std::string svg = contours_svg(rc);
  std::size_t paths = 0;
  for (std::size_t at = svg.find("<path"); at != std::string::npos; at = svg.find("<path", at + 1)) ++paths;
  EXPECT_EQ(paths, rc.labels.size());
}

}  // namespace
}  // namespace cmr::mesh
