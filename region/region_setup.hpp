#pragma once
// Internal to cmr::region and the libraries above it: a library user includes
// `region/region.hpp` (space curves: `region/space_region.hpp`).
// The backend interface (namespace cmr::backend): the host preparation of a
// region problem (RegionSetup, reached through RegionProblem::setup()) and the
// per-position and per-block classifiers that every RegionBackend shares
// (CpuRegionBackend here, cmr::vk::VulkanRegionBackend in vk/). Users who only
// render regions need region/region.hpp alone; this header is for those who
// write a backend. The layout of RegionSetup follows the GPU buffer layout
// (shaders/region_layout.h) and changes with it.
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
// rounding). Uncertain signs send the pixel to the exact path. The level-0
// test runs first, so most pixels cost two polynomial evaluations per touched
// segment.
//
// Labels travel here as their 8-bit codes (code() in region.hpp): the same
// word the shader returns; RegionResult decodes them into typed labels.
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <variant>
#include <vector>

#include "bezierize/analyze.hpp"
#include "numeric/bounded.hpp"
#include "numeric/exact.hpp"
#include "bezierize/extract.hpp"
#include "region/region.hpp"

namespace cmr::backend {

/// The request under the name the preparation code uses.

/// Throws InputError for an invalid request (see RegionProblem::make).
/// Called by prepare_region, the one entry to a prepared problem.
void validate_region_options(const BSpline& spline, const RegionRequest& options);

/// Which labels a request's pixels get: Direction, Split (split) or
/// Alternation (splits).
enum class Labels : uint8_t { plain, split, alternating, each_piece };
Labels labels_of(const RegionRequest& request);

/// What one position gets, with the label as its code.
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
  int part = 0;                                ///< its group: group_of(RegionSetup::cuts, segment)
  bool classify = true;                        ///< touched by the group
  std::vector<Point<Rational>> base_exact;     ///< B0: Bezier points before the move
  std::vector<Rational> weight_exact;          ///< w: B = B0 + w (dx, dy)
  std::vector<Point<Bounded>> base;            ///< B0 rounded, with bounds
  std::vector<Bounded> weight;                 ///< w rounded, with bounds
  /// Rational splines: base_exact/base hold the homogeneous (W x, W y) of the
  /// Bezier points, hw their weights W (fixed: the move keeps the weights),
  /// weight the influence c_i on (W x, W y) = B0 + c (dx, dy), i.e. the
  /// blossom of the data w_k on the group; xi and nu are then lambda (8n-11
  /// coefficients) and D (3n-5) of rational_lambda.hpp, still a cubic and an
  /// affine polynomial in (dx, dy) (D is multilinear in columns that move
  /// along one direction). Empty for a polynomial spline.
  std::vector<Rational> hw_exact;
  std::vector<Bounded> hw;
  /// xi_k(dx, dy) of every subdivision piece down to RegionSetup::piece_levels,
  /// rounded coefficients in poly3.hpp order: piece p (heap order: level L,
  /// index j at p = 2^L - 1 + j) has coefficient k at xi[p * (4n-6) + k].
  std::vector<std::array<double, 10>> xi;
  /// nu_k(dx, dy) = c0 + c1 dx + c2 dy per piece, at nu[p * (2n-3) + k].
  std::vector<std::array<double, 3>> nu;
  int n_xi = 0, n_nu = 0;  ///< coefficients per piece: 4n-6 and 2n-3 (rational: 8n-11 and 3n-5)
};

/// A joint whose curvature jump depends on the position (knot multiplicity
/// >= d-1 next to a touched segment), strictly inside a group.
struct RegionJoint {
  int joint = 0;         ///< index into RegionSetup::joints (joints().size() for the seam)
  int left = 0, right = 0;  ///< entry indices of its two segments
  int part = 0;             ///< its group
  bool seam = false;        ///< a closed spline's seam: the end of segment N-1 against the start of segment 0
};

/// The input of one position's verdict (part_verdict) with the untouched
/// segments folded: each run of consecutive segments that the move leaves
/// alone (no entry, no varying joint, not across a group's cut joint) becomes at
/// most three stand-in classes and two stand-in joints that part_verdict
/// reads exactly as it reads the run (fold_fixed_runs). A position then
/// costs O(entries) instead of O(segments), and the regions of all N points
/// of a spline cost O(N) in all rather than O(N^2).
struct VerdictTemplate {
  std::vector<SegmentClass> classes;  ///< entries' slots hold placeholders, filled per position
  std::vector<Joint> joints;          ///< joints[i-1] between classes i-1 and i (only `jump` is read)
  std::vector<int> slot;              ///< per segment: its index in classes, -1 where folded into a run
  std::vector<int> starts;            ///< index in classes where each group starts (starts[0] = 0)
};

/// Folds the judged segments (`range`) with needed[seg] == false (see
/// VerdictTemplate); segments outside the range are left out. Joint j
/// (joints[j], between segments j and j+1) stays a joint of its own when
/// either neighbour is needed or segment j+1 starts a group (a cut). For any
/// classes of the needed segments and any jumps of their joints,
/// group_verdicts over the template equals part_verdict over each group of
/// segment_groups(range, cuts) of the full lists, in `mode`, and the largest
/// decision depth over the template is the one over the range.
VerdictTemplate fold_fixed_runs(const std::vector<SegmentClass>& classes, const std::vector<Joint>& joints,
                                const std::vector<bool>& needed, SegmentRange range, const std::vector<int>& cuts,
                                Mode mode);

/// part_verdict of each group of a filled-in template, in group order.
std::vector<Direction> group_verdicts(const VerdictTemplate& t, const std::vector<SegmentClass>& classes,
                                      const std::vector<Joint>& joints, Mode mode);

/// Host preparation shared by the backends.
/// The spline before the move and its analysis (every segment classified to
/// max_depth, with inflections; the joints): shared by the problems of
/// several points of one spline (RegionProblem::make_each).
struct RegionBase {
  BSpline spline;
  SplineAnalysis analysis;
  int max_depth = 0;
};

struct RegionSetup {
  std::shared_ptr<const RegionBase> base;
  RegionRequest options;                 ///< validated, view resolved
  std::vector<int> group;                ///< k first, then the rigid members
  Vec2 anchor{0.0};                      ///< P_k
  SegmentRange range;                    ///< the judged segments (options.segments, or all)
  std::vector<int> cuts;                 ///< the joints between groups: options.split, or options.splits (each_piece_cuts)
  std::vector<RegionEntry> entries;      ///< ascending segment order, judged segments only
  std::vector<RegionJoint> varying;      ///< joints whose jump depends on p
  VerdictTemplate verdict;               ///< per-position verdict input (entries' slots filled per position)
  bool fixed_level0_none = false;        ///< an untouched judged segment fails at level 0, or a judged one has a pole: every pixel is 0
  bool fixed_none = false;               ///< an untouched judged segment fails at some level, or a judged one has a pole: every label is 0
  int piece_levels = 0;                  ///< L0: pieces down to this level have precomputed polynomials
  /// A closed spline's whole period without cuts: the seam is judged like
  /// every other joint (as analyze does): the verdict template ends with
  /// neutral_class() after segment N-1, the seam being the joint before it.
  bool around = false;
  /// The floating-point kernel works on the problem scaled by 2^-scale_exponent:
  /// the entries' Bezier points (base_exact, base; their piece polynomials xi,
  /// nu) and every displacement (kernel_displacement). A power of two scales
  /// every rounded value and every bound's |terms| exactly, and the labels do
  /// not change: each sign decided is that of a polynomial homogeneous in the
  /// coordinates (lambda, eta, the curvature jumps), so scaling them by a
  /// positive factor keeps it. Without it, coordinates near 2^+-300 put the
  /// polynomials' values (degree 4 and more in the coordinates) beyond the
  /// double range, and every pixel fell to the exact path.
  /// kernel_scale_exponent: 0 for ordinary data (the kernel then computes
  /// exactly what it computed before the scaling existed).
  int scale_exponent = 0;
  double scale = 1;  ///< 2^-scale_exponent

  const BSpline& spline() const { return base->spline; }                          ///< before the move
  const std::vector<SegmentClass>& fixed() const { return base->analysis.segments; }  ///< every segment's class before the move
  const std::vector<Joint>& joints() const { return base->analysis.joints; }          ///< before the move
  const Joint& seam() const { return *base->analysis.seam; }                          ///< closed splines only
};

/// The exponent e of RegionSetup::scale_exponent for a spline: 0 when the
/// largest control point coordinate M is 0 or lies in [2^-64, 2^64] (the
/// kernel's values, of degree at most 12 in the coordinates, stay inside
/// 2^+-768, far from overflow and from the 2^-1020 slack for underflow), and
/// otherwise the binary exponent of M (M 2^-e in [1, 2)).
int kernel_scale_exponent(const BSpline& spline);

/// A displacement d = fl(p - P_k) as the kernel takes it: d 2^-scale_exponent,
/// exact (one rounding relative to |d|, as before). Where scaling down would
/// make a non-zero d subnormal (and so inexact), NaN: every sign computed
/// from it is then uncertain, and the position goes to the exact path.
inline double kernel_displacement(const RegionSetup& s, double d) {
  const double scaled = d * s.scale;
  if (s.scale < 1 && d != 0 && !(std::fabs(scaled) >= 0x1p-1022)) return std::numeric_limits<double>::quiet_NaN();
  return scaled;
}

/// Levels of precomputed piece polynomials: deeper pieces are halved per pixel.
inline constexpr int kPieceLevels = 3;

/// The shared part of the problems of one spline at depth max_depth.
std::shared_ptr<const RegionBase> region_base(const BSpline& spline, int max_depth);

/// Validates (validate_region_options) and prepares. `base`, when given,
/// must be region_base(spline, options.max_depth) (shared between the
/// problems of several points); computed here otherwise.
/// `entries`, when given, supplies each entry instead of prepare_entry and
/// must return what prepare_entry returns for the same arguments (RegionMemo,
/// region/region_memo.hpp, remembers them between moves).
struct RegionSetup;
using EntrySource = std::function<RegionEntry(const RegionSetup& setup, int segment, bool classify)>;
RegionSetup prepare_region(const BSpline& spline, const RegionRequest& options,
                           std::shared_ptr<const RegionBase> base = nullptr, const EntrySource& entries = {});

/// The entry of judged segment `segment` of a setup whose group, options and
/// piece_levels are set: its Bezier points before the move and their
/// influence weights, and (with classify: the group touches it) its piece
/// polynomials. It depends on the segment's window alone (its 2d knots, d+1
/// points and weights, which of them the group holds) and piece_levels;
/// `part` is left 0 (prepare_region sets it).
RegionEntry prepare_entry(const RegionSetup& setup, int segment, bool classify);

/// The reference for one position: certified floating point, exact fallback.
PixelResult classify_position(const RegionSetup& setup, Vec2 p);
/// The exact path alone (what classify_position falls back to).
PixelResult classify_position_exact(const RegionSetup& setup, Vec2 p);

/// A working image's label codes, one byte per pixel, kept in the vector
/// RegionResult carries for the request's kind of label (Direction, Split,
/// Alternation or EachPiece: one-byte enums whose values are their codes,
/// written here through byte pointers), so that to_result hands them over
/// without copying (copying and checking them took about 21 us of a 250-300
/// us frame at 512x512; docs/performance.md).
class LabelCodes {
 public:
  LabelCodes() = default;
  LabelCodes(Labels kind, std::size_t count);                          ///< every code 0
  LabelCodes(Labels kind, const std::vector<std::uint8_t>& codes);  ///< these codes
  LabelCodes(const LabelCodes& other) : store_(other.store_) { bind(); }
  LabelCodes(LabelCodes&& other) noexcept : store_(std::move(other.store_)) {
    bind();
    other.bind();
  }
  LabelCodes& operator=(const LabelCodes& other);
  LabelCodes& operator=(LabelCodes&& other) noexcept;
  /// The kind of label the codes are kept as.
  Labels kind() const { return static_cast<Labels>(store_.index()); }
  std::size_t size() const { return size_; }
  std::uint8_t* data() { return data_; }
  const std::uint8_t* data() const { return data_; }
  std::uint8_t& operator[](std::size_t k) { return data_[k]; }
  std::uint8_t operator[](std::size_t k) const { return data_[k]; }
  const std::uint8_t* begin() const { return data_; }
  const std::uint8_t* end() const { return data_ + size_; }
  /// A copy of the codes (as RegionResult::codes() gives them).
  std::vector<std::uint8_t> codes() const { return {begin(), end()}; }
  /// The same codes (whatever kind they are kept as).
  bool operator==(const LabelCodes& other) const;
  /// Moves the codes into `r`'s label vector of their kind, leaving this empty.
  void move_into(RegionResult& r);

 private:
  void bind();  // data_ and size_ from store_
  // In the order of Labels' values.
  std::variant<std::vector<Direction>, std::vector<Split>, std::vector<Alternation>, std::vector<EachPiece>> store_;
  std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
};

/// A backend's working image: label codes.
struct RegionImage {
  int width = 0, height = 0;
  View view;
  LabelCodes labels;             ///< label codes, row-major, row 0 at the top
  std::vector<uint8_t> depth;    ///< decision level per pixel
  std::uint64_t exact_pixels = 0;
};

/// The certified fast path over a block of pixels (columns i0..i1, rows
/// j0..j1, inclusive): the result every pixel of the block gets, or nullopt
/// when the block is not uniform or a sign is not certain over it.
std::optional<PixelResult> classify_block(const RegionSetup& setup, int i0, int j0, int i1, int j1);

/// The displacements (scaled as the kernel takes them) of the centres of
/// pixel columns i0..i1 (rows j0..j1), inclusive, as a centre and a
/// half-width that enclose their exact values: the box of a block proof
/// (classify_block; the Vulkan backend's tile proofs). NaN where scaling
/// would be inexact (no proof then).
Bounded block_columns(const RegionSetup& setup, int i0, int i1);
Bounded block_rows(const RegionSetup& setup, int j0, int j1);

/// Block size of the CPU backend's (and the Vulkan backend's host) culling.
inline constexpr int kRegionBlock = 64;

/// An all-zero image of the setup's size and view.
RegionImage blank_image(const RegionSetup& setup);

/// Decides what the host can by blocks (quartering undecided blocks) into
/// img, and returns the pixels of undecided blocks whose sides are at most
/// min_block, for a device to classify; with min_block == 1 every pixel is
/// decided here and nothing is returned.
std::vector<std::array<int, 2>> region_cull(const RegionSetup& setup, RegionImage& img, int min_block, int threads);

/// Tells the worker pool that region_cull's batch is coming, where it will
/// have one (several blocks on several threads, and something to decide):
/// its sleeping workers wake while the caller clears the image
/// (WorkerPool::wake; docs/performance.md, "A render wakes its workers
/// before it clears its image").
void wake_cull_workers(const RegionSetup& setup, int threads);

/// The CPU render, on `threads` threads (0: all cores): blocks of pixels
/// decided whole where classify_block holds, quartered down to single pixels
/// through classify_position elsewhere. Every pixel gets exactly
/// classify_position's label.
RegionImage region_cpu(const RegionSetup& setup, int threads = 0);

/// The typed label of a code; InputError-free: codes come from code().
Direction region_label(uint8_t code);
Split split_label(uint8_t code);
Alternation alternating_label(uint8_t code);
EachPiece piece_label(uint8_t code);
/// A pixel's public form.
RegionPixel to_pixel(const PixelResult& r, Labels kind);
/// An image's public form (its codes moved into the vector of their kind;
/// seconds left 0).
RegionResult to_result(RegionImage&& image);
/// Checks (CMR_CHECK) that every code is below its kind's count of codes: a
/// device's output, which to_result takes as it is.
void check_codes(const LabelCodes& codes);

}  // namespace cmr::backend
