#pragma once
// Internal to cmr::region and the libraries above it: a library user includes
// `region/region.hpp` (space curves: `region/space_region.hpp`).
// Vector contours of a rendered region (marching squares), with every
// boundary vertex refined by bisection with the certified classifier.
//
// Samples. The label map of a RegionResult gives one sample per pixel centre
// (pixel_center), with the label of the request's kind (label_code: plain,
// split, alternating or each-piece; every classification below uses the same
// kind). A ring of samples on the view's edge surrounds them: one on each
// edge level with every pixel row and column, and the four view corners,
// each classified with the certified classifier (the map has none there).
// The cells (2x2 samples) tile the view rectangle exactly: pixel-sized inside,
// half a pixel wide along the edges, a quarter pixel at the corners.
//
// Cells. Corners c0..c3 in counter-clockwise world order (bottom-left,
// bottom-right, top-right, top-left). Walking c0 -> c1 -> c2 -> c3 -> c0, on
// each edge whose ends' labels differ lie the vertex of the first end's label
// and that of the second end's (one point when the bisection from one end
// ended at the other's label, see below). The central polygon is the edge
// vertices in walk order; where it has three or more points (three labels
// meet, a saddle, or an edge with two vertices) it belongs to one owner: the
// undecided band when an edge of the cell has an undecided stretch (below),
// else the label the classifier gives its centroid (the band's if that is
// undecided and no corner is). A label's pieces in a cell: the owner's is the
// whole walk less the other labels' corners (corners of its own label and
// every edge vertex); any other label's, one triangle-or-more per run of
// consecutive corners with that label, from the vertex before the run to the
// one after it (a saddle not owned by L: two separate triangles). Every piece
// has its vertices on the cell's boundary in boundary order, so it is a
// convex counter-clockwise polygon, and the pieces of all labels and the band
// tile the cell: the label areas and the band's sum to the view's area up to
// rounding. Outlines are the piece edges whose reverse is no piece edge of
// the same label, chained into closed loops: counter-clockwise around a
// region, clockwise around a hole (along the view's edge the region's own
// edge is its outline).
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
// in it. The cells with such a stretch on an edge give their central polygon
// to the band (RegionContours::band, name "undecided-band"). Undecided pixels
// keep their own label as before.
//
// Area. The shoelace formula on the loops (signed: holes negative) gives each
// label's area; the convex pieces triangulate the same set (fans), so the sum
// of their triangles' areas equals it up to rounding (tests check both).
#include <cstdint>
#include <vector>

#include "region/region.hpp"

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
  /// Every vertex: samples with label L (pixel centres and points of the
  /// view's edge) and refined boundary points.
  std::vector<Vec2> vertices;
  /// Per vertex: true for a refined boundary point (a certified change from
  /// or to this label lies within tolerance / 2 of it), false for samples
  /// and for other labels' vertices on the owner's piece of a cell.
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
  bool split = false;        ///< label codes are Split codes
  bool alternating = false;  ///< label codes are Alternation codes
  bool each_piece = false;   ///< label codes are EachPiece codes
  std::vector<LabelContours> labels;
  /// The band undecided at the depth limit between two decided labels,
  /// narrower than a pixel (so no pixel centre is in it): label
  /// kUndecidedBandLabel, pieces and outlines as above, area the shoelace
  /// sum; empty when no cell's central polygon is the band's.
  LabelContours band;
  std::uint64_t bisections = 0;  ///< refined edges (classify runs ~log2(1/tolerance) times each)

  /// The name of label code `c` of this map's kind (RegionResult::label_name;
  /// kUndecidedBandName for the band).
  const char* label_name(std::uint8_t c) const;
};

/// Signed area of a closed polygon (shoelace; counter-clockwise positive).
double polygon_area(const std::vector<Vec2>& vertices, const std::vector<int>& loop);

/// The contours of `region`, rendered from `problem` (same size, view and
/// kind of label; InputError otherwise), refined with problem.classify read
/// as the request's kind of label (label_code).
RegionContours region_contours(const RegionProblem& problem, const RegionResult& region,
                               const ContourOptions& options = {});

}  // namespace cmr
