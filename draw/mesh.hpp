#pragma once
/// Region geometry as triangle meshes (OpenMesh) and vector files (library
/// target cmr::mesh; no CLI, no file output: bytes in memory, written by the
/// caller with cmr::write_file_atomic).
///
/// Region meshes: every label's convex contour pieces (region/contour.hpp)
/// as triangle fans, one OpenMesh TriMesh for all labels; a piece's vertices
/// are shared with its neighbours (pixel centres and edge vertices have one
/// index per label), so each label is a 2-manifold with boundary whose holes
/// are the holes of its region and whose area equals the contour area.
///
/// Region tubes: the stack of a sweep's label maps as voxels (x, y, knot)
/// and the surface around the voxels that are "in" (marching tetrahedra):
/// each cube of 2x2x2 samples of the padded stack (one ring of "out" samples)
/// is split into the six Kuhn tetrahedra around its main diagonal, the same
/// split in every cube, so neighbouring tetrahedra share faces with the same
/// diagonal. In every tetrahedron whose samples are not all alike, the iso
/// surface of the piecewise linear interpolation of in = +1 / out = -1 is a
/// triangle (one sample differs) or a quadrilateral (two and two), with
/// vertices at the midpoints of the edges whose ends differ. The pieces join
/// along shared tetrahedron faces, so the surface is a closed 2-manifold that
/// separates the "in" samples from the padding; each triangle is oriented
/// with its normal towards the "out" samples of its tetrahedron. A voxel
/// spans half a sample spacing each side of its centre, so the surface meets
/// the view's edges and lies half a knot step beyond the first and last knot.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

// OpenMesh's property containers value-initialise through a path GCC 12
// reports as maybe-uninitialized (in OpenMesh's headers, not here).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#pragma GCC diagnostic pop

#include "region/contour.hpp"
#include "spline/fields.hpp"

namespace cmr::mesh {

/// Double-precision points; vertex colours for the PLY writer.
struct Traits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Color);
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

/// The label code of each vertex of a region mesh (a property named "label").
inline constexpr const char* kLabelProperty = "label";

/// The triangulated regions of every label (z = 0), with per-vertex label
/// codes and colours (the legend of draw/draw.hpp).
Mesh region_mesh(const RegionContours& contours);

/// The label code of vertex v of a region mesh.
std::uint8_t vertex_label(const Mesh& mesh, Mesh::VertexHandle v);

/// Sum of the triangles' areas.
double mesh_area(const Mesh& mesh);
/// Signed enclosed volume (divergence theorem; positive for outward normals).
double mesh_volume(const Mesh& mesh);
/// No boundary edges: every edge has two faces.
bool is_closed(const Mesh& mesh);

/// A sweep's label maps as voxels: `in` is width * height * knots.size()
/// booleans, slice k (knot value knots[k]) row-major, row 0 at the top of
/// `view` (pixel_center). Knots are equally spaced and increasing; with one
/// knot the knot step is 1.
struct VoxelStack {
  int width = 0, height = 0;
  View view;
  std::vector<double> knots;
  std::vector<bool> in;
};

/// The closed surface around the "in" voxels (marching tetrahedra, see
/// above), points (x, y, knot). InputError for an inconsistent stack.
Mesh tube_mesh(const VoxelStack& stack);

/// Wavefront OBJ text: "v x y z" with 17 significant digits, "f a b c"
/// (1-based); for region meshes one group "g label_N" per label.
std::string obj_text(const Mesh& mesh);
/// ASCII PLY: x y z (17 significant digits), red green blue (uchar) and,
/// when the mesh has labels, label (uchar) per vertex; triangles.
std::string ply_text(const Mesh& mesh);
/// SVG of the outlines: one path per label (outer loops counter-clockwise,
/// holes clockwise, nonzero fill), filled with the label's colour, in world
/// coordinates (y up, 17 significant digits); a frame at the view's edge.
std::string contours_svg(const RegionContours& contours);

/// The contour file for `path`, by its extension (case-insensitive): .svg
/// contours_svg, .obj obj_text(region_mesh), .ply ply_text(region_mesh).
/// InputError naming `option` for any other extension.
std::string contour_file(const std::filesystem::path& path, const RegionContours& contours,
                         const std::string& option = field("contours"));
/// The InputError of contour_file for a bad extension, before any work.
void check_contour_file_name(const std::filesystem::path& path, const std::string& option = field("contours"));

}  // namespace cmr::mesh
