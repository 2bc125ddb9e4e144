// cmr region SPACE.json --point K --plane P --mesh OUT.obj|OUT.ply: the files
// parse back with OpenMesh, the patch's vertices lie in the plane, the tube's
// at its radius from the curve, the counts match the summary; bad mesh paths
// exit 2 with one line and leave files as they were; a device is written,
// never replaced.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // in OpenMesh's headers (see draw/mesh.hpp)
#include <OpenMesh/Core/IO/MeshIO.hh>
#pragma GCC diagnostic pop

#include <sys/stat.h>

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "draw/space_mesh.hpp"
#include "tests/cli_util.hpp"

namespace cmr {
namespace {

namespace fs = std::filesystem;
const std::string kCurve = std::string(CMR_SOURCE_DIR) + "/examples/space/fig8b_lifted.json";
const std::string kRegion = "region " + kCurve + " --point 3 --plane xy --view -1.2,-1.2,0.8,0.8 --size 40x40";

double distance_to_curve(const SpaceSpline& s, const Vec3& p) {
  double best = 1e300, bt = 0;
  const int n = 3000;
  for (int i = 0; i <= n; ++i) {
    const double t = s.domain_begin() + (s.domain_end() - s.domain_begin()) * i / n;
    const double d = glm::length(evaluate(s, t) - p);
    if (d < best) best = d, bt = t;
  }
  double h = (s.domain_end() - s.domain_begin()) / n;
  for (int it = 0; it < 60; ++it, h *= 0.7)
    for (const double t : {bt - h, bt + h}) {
      const double tc = std::clamp(t, s.domain_begin(), s.domain_end());
      const double d = glm::length(evaluate(s, tc) - p);
      if (d < best) best = d, bt = tc;
    }
  return best;
}

TEST(SpaceMeshCli, PlyAndObjParseBackPatchInPlaneTubeAtRadius) {
  const SpaceSpline s = read_space_spline_file(kCurve);
  const double z = s.points()[3].z;  // the xy plane through P3
  for (const std::string ext : {".ply", ".obj"}) {
    const fs::path out = test::scratch() / ("region" + ext);
    const test::Outcome r = test::run(kRegion + " --tube-radius 0.05 --mesh " + out.string());
    ASSERT_EQ(r.code, 0) << r.err;
    const auto summary = nlohmann::json::parse(r.out);
    mesh::Mesh m;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(m, out.string())) << ext;
    EXPECT_EQ(m.n_faces(), summary["mesh"]["faces"].get<std::size_t>()) << ext;
    EXPECT_EQ(summary["mesh"]["tube_radius"], 0.05);
    // Patch and tube: the PLY's label column (255: the tube), the OBJ's groups.
    std::vector<int> labels;
    const std::string text = test::slurp(out);
    if (ext == ".ply") {
      std::istringstream in(text.substr(text.find("end_header\n") + 11));
      for (std::size_t v = 0; v < m.n_vertices(); ++v) {
        double x, y, zz;
        int red, green, blue, label;
        in >> x >> y >> zz >> red >> green >> blue >> label;
        labels.push_back(label);
      }
    } else {
      EXPECT_NE(text.find("g label_255\n"), std::string::npos);
      EXPECT_NE(text.find("g label_0\n"), std::string::npos);  // "none": P3 anywhere in most of the view
    }
    int patch = 0, tube = 0;
    for (const auto v : m.vertices()) {
      const auto p = m.point(v);
      const Vec3 q(p[0], p[1], p[2]);
      const bool is_tube = ext == ".ply" ? labels[static_cast<std::size_t>(v.idx())] == 255
                                         : std::abs(q.z - z) > 1e-6 || distance_to_curve(s, q) < 0.06;
      if (is_tube) {
        ++tube;
        const double d = distance_to_curve(s, q);
        EXPECT_TRUE(std::abs(d - 0.05) < 1e-5 || d < 1e-5) << ext << " tube vertex " << v.idx() << " at " << d;
      } else {
        ++patch;
        EXPECT_NEAR(q.z, z, 1e-6) << ext << " patch vertex " << v.idx();
        EXPECT_GE(q.x, s.points()[3].x - 1.2 - 1e-6);
        EXPECT_LE(q.x, s.points()[3].x + 0.8 + 1e-6);
      }
    }
    EXPECT_GE(patch, 8) << ext;  // two labels at least: two rectangles
    EXPECT_LE(patch, 4 * 40 * 40) << ext;
    EXPECT_GE(tube, 16 * 10) << ext;
  }
}

void expect_one_line_exit2(const test::Outcome& r, const std::string& start) {
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("cmr: " + start, 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(SpaceMeshCli, BadMeshPathsExit2WithOneLine) {
  const fs::path dir = test::scratch();
  expect_one_line_exit2(test::run(kRegion + " --mesh " + (dir / "nowhere" / "r.ply").string()),
                        "--mesh " + (dir / "nowhere" / "r.ply").string() + ": the folder");
  expect_one_line_exit2(test::run(kRegion + " --mesh " + (dir / "r.stl").string()),
                        "--mesh " + (dir / "r.stl").string() + ": expected a file name ending in .obj or .ply");
  expect_one_line_exit2(test::run(kRegion + " --mesh " + dir.string()), "--mesh " + dir.string());
  expect_one_line_exit2(test::run(kRegion + " --tube-radius -1 --mesh " + (dir / "r.ply").string()),
                        "--tube-radius: must be a positive number");
  expect_one_line_exit2(test::run("region " + std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8.json --point 3 --mesh " +
                                  (dir / "r.ply").string()),
                        "--mesh is for space curves");
  // A failing run leaves an existing file as it was (all outputs or none).
  const std::string keep = test::write("keep.obj", "old\n");
  const std::string png = (dir / "p.png").string();
  expect_one_line_exit2(test::run("region " + kCurve + " --point 3 --size 40x40 --mesh " + keep + " --png " + png +
                                  " --plane 0,0,0,1,0,0,2,0,0"),
                        "--plane: U and V are parallel");
  EXPECT_EQ(test::slurp(keep), "old\n");
  EXPECT_FALSE(fs::exists(png));
}

TEST(SpaceMeshCli, DeviceIsWrittenNotReplaced) {
  // The format comes from the name: a link named .ply to /dev/null.
  const fs::path link = test::scratch() / "null.ply";
  fs::remove(link);
  fs::create_symlink("/dev/null", link);
  const test::Outcome r = test::run(kRegion + " --mesh " + link.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(link));
  struct stat st {};
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
}

}  // namespace
}  // namespace cmr
