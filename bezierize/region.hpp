#pragma once
// Curvature monotonicity regions (CAD&A 2024 §3-4): for every pixel, put a
// control point there and decide whether the curvature of the whole spline is
// monotone. This header holds what every backend shares: the one mapping from
// pixels to world coordinates, the host preparation, the per-position
// classification (the reference), and the CPU backend.
//
// Semantics of one position p: control point k moves to p and every point of
// its rigid group moves by the same translation p - P_k (exactly, in rational
// arithmetic); the label is the spline-level verdict (analyze.hpp) of the
// spline so changed, with every sign decision exact.
//
// Decision level of a pixel (the depth map, Fig. 7): 0 when some segment
// proves non-monotonicity at level 0 (xi_0 xi_last < 0; in CMR mode also
// nu_0 nu_last <= 0, an inflection); otherwise the deepest level any segment
// needed. The level-0 test runs first, so most pixels cost two polynomial
// evaluations per touched segment. Without a depth map (RegionOptions::depth
// false) only labels are produced, and every depth reads 0.
//
// Fast path: B_i = B0_i + w_i (dx, dy) is affine in the displacement, so each
// xi_k is a cubic and each nu_k an affine polynomial in (dx, dy) (poly3.hpp),
// and so are the Bernstein coefficients of every subdivision piece.
// Their coefficients are computed exactly on the host once (down to level
// kPieceLevels) and rounded; per pixel Algorithms 1 and 2 visit the pieces in
// the same depth-first order, evaluating only the coefficients a decision
// needs, each with a rigorous error bound
//     |fl(P) - P| <= kPolyErrorUnits * u * sum_m |C_m| |mu_m| + tiny
// (dx carries one rounding, the monomials two, the coefficient one, the
// product one, the sum nine: 16 units; 24 leaves slack for the bound's own
// rounding). Uncertain signs send the pixel to the exact path.
//
// Labels (8-bit): without split 0 not monotone, 1 increasing, 2 decreasing,
// 3 undecided at the depth limit. With split: 0 none, 1 inc-inc, 2 inc-dec
// (maximum at the joint), 3 dec-inc (minimum), 4 dec-dec, 5 undecided.
#include <cstdint>
#include <optional>
#include <vector>

#include "bezierize/analyze.hpp"
#include "bezierize/bounded.hpp"
#include "bezierize/exact.hpp"
#include "bezierize/extract.hpp"
#include <array>

namespace cmr {

/// World rectangle shown by an image: x0 left, x1 right, y0 bottom, y1 top.
struct View {
  double x0 = 0, y0 = 0, x1 = 1, y1 = 1;
};

inline constexpr int kMaxImageSize = 16384;

/// Centre of pixel (i, j), row 0 at the top: x = x0 + ((x1-x0)(i+0.5))/W,
/// y = y1 - ((y1-y0)(j+0.5))/H, in double, in that order. The one place that
/// maps pixels to world coordinates (the shader mirrors it operation by operation).
inline Vec2 pixel_center(const View& v, int width, int height, int i, int j) {
  const double x = v.x0 + ((v.x1 - v.x0) * (i + 0.5)) / width;
  const double y = v.y1 - ((v.y1 - v.y0) * (j + 0.5)) / height;
  return {x, y};
}

/// The control polygon's bounding box with a 25% margin, widened in one
/// direction so that pixels are square.
View default_view(const BSpline& spline, int width, int height);

struct RegionOptions {
  int point = 0;                 ///< k: the control point placed at each pixel
  std::vector<int> with;         ///< other points moving rigidly with k
  Mode mode = Mode::cmrwi;       ///< cmrwi: monotone; cmr: monotone, no inflection
  std::optional<int> split;      ///< joint s: segments 0..s-1 against s..N-1
  int max_depth = 12;            ///< D of Algorithms 1 and 2
  int width = 512, height = 512;
  std::optional<View> view;      ///< default_view() when empty
  /// Compute each pixel's decision level (the depth map). Without it, blocks
  /// can be labelled "not monotone" by a proof that skips each pixel's own
  /// traversal (faster), and RegionImage::depth is all zero.
  bool depth = true;
};

/// Throws InputError for a point out of range, a size of 0 or above
/// kMaxImageSize, a split outside 1..N-1, a depth outside 0..30, a view
/// with zero or non-finite extent.
void validate_region_options(const BSpline& spline, const RegionOptions& options);

uint8_t label_of(Direction d);
uint8_t label_of(Split s);

/// What one position gets.
struct PixelResult {
  uint8_t label = 0;
  uint8_t depth = 0;    ///< deepest level any segment needed
  bool exact = false;   ///< the exact path ran
};

inline constexpr double kPolyErrorUnits = 24;

/// A segment whose Bezier points the move changes (or, with classify ==
/// false, an untouched neighbour of a joint whose curvature jump varies).
struct RegionEntry {
  int segment = 0;
  int part = 0;                                ///< 1 for segments at or after the split joint
  bool classify = true;                        ///< touched by the group
  std::vector<Point<Rational>> base_exact;     ///< B0: Bezier points before the move
  std::vector<Rational> weight_exact;          ///< w: B = B0 + w (dx, dy)
  std::vector<Point<Bounded>> base;            ///< B0 rounded, with bounds
  std::vector<Bounded> weight;                 ///< w rounded, with bounds
  /// xi_k(dx, dy) of every subdivision piece down to RegionSetup::piece_levels,
  /// rounded coefficients in poly3.hpp order: piece p (heap order: level L,
  /// index j at p = 2^L - 1 + j) has coefficient k at xi[p * (4n-6) + k].
  std::vector<std::array<double, 10>> xi;
  /// nu_k(dx, dy) = c0 + c1 dx + c2 dy per piece, at nu[p * (2n-3) + k].
  std::vector<std::array<double, 3>> nu;
  int n_xi = 0, n_nu = 0;  ///< coefficients per piece: 4n-6 and 2n-3
};

/// A joint whose curvature jump depends on the position (knot multiplicity
/// >= d-1 next to a touched segment), strictly inside a part.
struct RegionJoint {
  int joint = 0;         ///< index into RegionSetup::joints
  int left = 0, right = 0;  ///< entry indices of its two segments
  int part = 0;
};

/// Host preparation shared by the backends.
struct RegionSetup {
  BSpline spline;
  RegionOptions options;                 ///< validated, view resolved
  std::vector<int> group;                ///< k first, then the rigid members
  Vec2 anchor{0.0};                      ///< P_k
  std::vector<RegionEntry> entries;      ///< ascending segment order
  std::vector<RegionJoint> varying;      ///< joints whose jump depends on p
  std::vector<SegmentClass> fixed;       ///< every segment's class before the move
  std::vector<Joint> joints;             ///< before the move
  bool fixed_level0_none = false;        ///< an untouched segment fails at level 0: every pixel is 0
  bool fixed_none = false;               ///< an untouched segment fails at some level: every label is 0
  int piece_levels = 0;                  ///< L0: pieces down to this level have precomputed polynomials
};

/// Levels of precomputed piece polynomials: deeper pieces are halved per pixel.
inline constexpr int kPieceLevels = 3;

RegionSetup prepare_region(const BSpline& spline, const RegionOptions& options);

/// The reference for one position: certified floating point, exact fallback.
PixelResult classify_position(const RegionSetup& setup, Vec2 p);
/// The exact path alone (what classify_position falls back to).
PixelResult classify_position_exact(const RegionSetup& setup, Vec2 p);

struct RegionImage {
  int width = 0, height = 0;
  View view;
  std::vector<uint8_t> labels;   ///< row-major, row 0 at the top
  std::vector<uint8_t> depth;    ///< decision level per pixel
  std::uint64_t exact_pixels = 0;
};

/// The certified fast path over a block of pixels (columns i0..i1, rows
/// j0..j1, inclusive): the result every pixel of the block gets, or nullopt
/// when the block is not uniform or a sign is not certain over it.
std::optional<PixelResult> classify_block(const RegionSetup& setup, int i0, int j0, int i1, int j1);

/// Block size of the CPU backend's (and the Vulkan backend's host) culling.
inline constexpr int kRegionBlock = 64;

/// An all-zero image of the setup's size and view.
RegionImage blank_image(const RegionSetup& setup);

/// Decides what the host can by blocks (quartering undecided blocks) into
/// img, and returns the pixels of undecided blocks whose sides are at most
/// min_block, for a device to classify; with min_block == 1 every pixel is
/// decided here and nothing is returned.
std::vector<std::array<int, 2>> region_cull(const RegionSetup& setup, RegionImage& img, int min_block, int threads);

/// CPU backend, on `threads` threads (0: all cores): blocks of pixels decided
/// whole where classify_block holds, quartered down to single pixels through
/// classify_position elsewhere. Every pixel gets exactly classify_position's label.
RegionImage region_cpu(const RegionSetup& setup, int threads = 0);

}  // namespace cmr
