#pragma once
/// 3D export of a space curve's plane region (issue 25, docs/space.md): the
/// curve as a tube and the region as a patch in its plane, one OpenMesh
/// triangle mesh (draw/mesh.hpp's Mesh: double points, vertex colours, a
/// "label" vertex property), written as OBJ or PLY text by mesh::obj_text /
/// mesh::ply_text (the caller writes the bytes, through an OutputSet).
///
/// The patch: the label map's pixels as rectangles in the plane Q(a, b) = O +
/// a U + b V, pixel (i, j) covering [x0 + (x1-x0) i/W, x0 + (x1-x0)(i+1)/W] x
/// [y1 - (y1-y0)(j+1)/H, y1 - (y1-y0) j/H] of the view (row 0 at the top, as
/// pixel_center), coloured and labelled by the pixel's label code (the legend
/// colours of draw/draw.hpp). Pixels are merged where it pays: each row's runs
/// of one label, and a run continues the rectangle above it when that one
/// has the same columns and label; each rectangle is two triangles with four
/// vertices of its own. A one-label map is 2 triangles, a W x H map of
/// alternating labels 2WH.
///
/// The tube: circles of `sides` vertices around sample points C(t_k) in the
/// plane normal to C'(t_k), oriented by rotation-minimising frames (the
/// double reflection method, Wang et al. 2008), joined by triangles. The
/// samples are adaptive: every segment is split in halves until the tangent
/// turns by at most `max_turn` radians between neighbouring samples (and at
/// each half's midpoint), at most 2^12 pieces per segment. An open curve's
/// tube is closed by a fan at each end (its centre on the curve); a closed
/// curve's last circle joins its first (the frames' twist over the loop is
/// spread evenly). Tube vertices have label kTubeLabel and a dark grey colour.
#include <cstdint>
#include <filesystem>
#include <string>

#include "region/region.hpp"
#include "region/space_region.hpp"
#include "draw/mesh.hpp"
#include "spline/space.hpp"

namespace cmr::mesh {

/// The "label" of the tube's vertices (region label codes are below 16).
inline constexpr std::uint8_t kTubeLabel = 255;

struct TubeOptions {
  double radius = 0;  ///< > 0
  int sides = 16;     ///< vertices per circle, >= 3
  double max_turn = 0.15;  ///< radians of tangent turn between samples
};

/// The sample parameters of the tube (increasing; the domain's ends included).
std::vector<double> tube_parameters(const SpaceSpline& spline, double max_turn);
/// The tube around `spline`. InputError for a radius that is not > 0 and finite.
Mesh curve_tube(const SpaceSpline& spline, const TubeOptions& options);
/// The region's label map as merged rectangles in `plane` (see above).
Mesh plane_patch(const RegionResult& region, const SpacePlane& plane);
/// Appends `part`'s vertices (colour, label) and faces to `mesh`.
void append(Mesh& mesh, const Mesh& part);
/// The default tube radius: 0.4% of the diagonal of the control points'
/// bounding box (1e-3 when the points coincide).
double default_tube_radius(const SpaceSpline& spline);

/// InputError unless `path` ends in .obj or .ply (case-insensitive):
/// "OPTION PATH: expected a file name ending in .obj or .ply".
void check_mesh_file_name(const std::filesystem::path& path, const std::string& option = field("mesh"));
/// obj_text or ply_text of `mesh`, by `path`'s extension.
std::string mesh_file(const std::filesystem::path& path, const Mesh& mesh, const std::string& option = field("mesh"));

}  // namespace cmr::mesh
