#pragma once
// Vector contours of a rendered region (marching squares), with every
// boundary vertex refined by bisection with the certified classifier.
//
// Samples. The label map of a RegionResult gives one sample per pixel centre
// (pixel_center). The grid is padded with one ring of "outside" samples one
// pixel spacing beyond the outermost centres; a vertex on an edge between a
// pixel centre and a padding sample is put at the view's edge (halfway), so
// regions are clipped to the view rectangle. (The padding corners are not
// cells' corners of any region, so at each view corner a right triangle with
// legs of half a pixel is cut off a region that fills the corner.)
//
// Per label L, the cell (2x2 samples) walk: corners in counter-clockwise
// world order c0..c3 (bottom-left, bottom-right, top-right, top-left); walking
// c0 -> c1 -> c2 -> c3 -> c0, every corner with label L is emitted, and
// between consecutive corners whose membership differs the vertex on that edge
// is emitted. The emitted vertices lie on the cell's boundary in boundary
// order, so the piece is a convex polygon with the region on its left. The
// two saddle cases (L exactly at two diagonal corners) are resolved as
// separated: two triangles, one at each corner, so that the pieces of
// different labels never overlap in a cell. Where the piece leaves L (edge k:
// c_k in, c_{k+1} out) to where it comes back, its edge is a piece of the
// outline, oriented with L on the left; every edge vertex has exactly one
// outgoing and one incoming outline edge, so the outline edges chain into
// closed loops: counter-clockwise around a region, clockwise around a hole.
//
// Refinement. The vertex on an edge from sample a (label L) to sample b (not
// L) is found by bisection of t in [0, 1] on p(t) = a + t (b - a), keeping
// classify(p(lo)) == L and classify(p(hi)) != L, until |p(hi) - p(lo)| <=
// tolerance * min(view width, view height) (or until lo and hi are adjacent
// doubles); the vertex is p((lo + hi) / 2), so it lies within half the
// tolerance of a point where the certified label changes from L. classify is
// exact (RegionProblem::classify), so "changes" is the true label boundary
// sampled along the edge, not an approximation of it. One edge between labels
// L and M is bisected once when its bracket ends at M (then it serves both
// labels), twice otherwise.
//
// The undecided band. Where the bisection from label L towards M meets the
// undecided label (Algorithm 1 at the depth limit) before M, the vertex of L
// lies on the boundary of L's certified label and a second bisection from M
// puts M's vertex on the boundary of M's: the stretch between them is
// undecided, and the exact boundary of L (at unlimited depth) lies somewhere
// in it. Those stretches make the band (RegionContours::band, name
// "undecided-band"): in each cell with such a stretch on an edge, the part of
// the cell no label's piece covers (the polygon of the cell's edge vertices,
// counter-clockwise). Undecided pixels keep their own label as before.
//
// Area. The shoelace formula on the loops (signed: holes negative) gives each
// label's area; the convex pieces triangulate the same set (fans), so the sum
// of their triangles' areas equals it up to rounding (tests check both).
#include <cstdint>
#include <vector>

#include "bezierize/region.hpp"

namespace cmr {

/// Options of region_contours.
struct ContourOptions {
  /// Bisection stops when the bracket is at most this times the smaller side
  /// of the view.
  double tolerance = 1e-9;
  int threads = 0;  ///< parallel_for threads for the bisections (0: every core)
};

/// The geometry of one label.
struct LabelContours {
  std::uint8_t label = 0;  ///< the label code (code())
  /// Every vertex: pixel centres with label L, refined boundary points, and
  /// points on the view's edge.
  std::vector<Vec2> vertices;
  /// Per vertex: true for a refined boundary point (a certified label change
  /// lies within tolerance / 2 of it), false for pixel centres and view-edge points.
  std::vector<bool> refined;
  /// Convex pieces (vertex indices, counter-clockwise); their union is the
  /// label's region as sampled.
  std::vector<std::vector<int>> pieces;
  /// Closed outlines (vertex indices, the first not repeated at the end):
  /// counter-clockwise around regions, clockwise around holes.
  std::vector<std::vector<int>> outlines;
  double area = 0;  ///< shoelace sum over the outlines (world units squared)
};

/// LabelContours::label of the undecided band (no label code of a map).
inline constexpr std::uint8_t kUndecidedBandLabel = 254;
/// Its name in `areas` and the SVG.
inline constexpr const char* kUndecidedBandName = "undecided-band";

/// All labels present in the map, in increasing code order.
struct RegionContours {
  View view;
  bool split = false;  ///< label codes are Split codes
  std::vector<LabelContours> labels;
  /// The band undecided at the depth limit between two decided labels,
  /// narrower than a pixel (so no pixel centre is in it): label
  /// kUndecidedBandLabel, pieces and outlines as above, area the shoelace
  /// sum; empty when no bisection met the undecided label.
  LabelContours band;
  std::uint64_t bisections = 0;  ///< refined edges (classify runs ~log2(1/tolerance) times each)
};

/// Signed area of a closed polygon (shoelace; counter-clockwise positive).
double polygon_area(const std::vector<Vec2>& vertices, const std::vector<int>& loop);

/// The contours of `region`, rendered from `problem` (same size, view and
/// labels; InputError otherwise), refined with problem.classify.
RegionContours region_contours(const RegionProblem& problem, const RegionResult& region,
                               const ContourOptions& options = {});

}  // namespace cmr
