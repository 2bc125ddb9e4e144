#pragma once
// Curvature monotonicity regions (CAD&A 2024 §3-4), the public API: for every
// pixel, put a control point there and decide whether the curvature of the
// whole spline is monotone.
//
//   RegionRequest  what to compute (an aggregate with defaults);
//   RegionProblem  the request validated (once) and prepared; reusable for
//                  many renders and for single positions (classify);
//   RegionBackend  renders a problem into a RegionResult: CpuRegionBackend
//                  here, cmr::vk::VulkanRegionBackend in vk/region_vk.hpp.
//
// Semantics of one position p: control point k moves to p and every point of
// its rigid group moves by the same translation p - P_k (exactly, in rational
// arithmetic); the label is the spline-level verdict (analyze.hpp) of the
// spline so changed, with every sign decision exact. Every backend gives
// every pixel exactly that label (certified floating point, exact rational
// arithmetic where the bounds do not decide), so backends and precisions
// agree pixel by pixel.
//
// Decision level of a pixel (the depth map, Fig. 7): 0 when some segment
// proves non-monotonicity at level 0 (xi_0 xi_last < 0; in CMR mode also
// nu_0 nu_last <= 0, an inflection); otherwise the deepest level any segment
// needed. Without a depth map (RegionRequest::depth false) only labels are
// produced, and every depth reads 0.
//
// How the fast path is certified: region/region_setup.hpp.
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bezierize/analyze.hpp"
#include "spline/bspline.hpp"
#include "spline/errors.hpp"
#include "spline/limits.hpp"

namespace cmr {

namespace backend {
struct RegionSetup;
}

/// A pixel's label is the verdict itself: Direction (plain), Split (--split
/// S: parts 0..S-1 and S..N-1; inc_dec is a signed-curvature maximum at joint
/// S), Alternation (several joints) or EachPiece (each piece on its own); one
/// vocabulary with analyze, the report and the gates, and one to_string each
/// (analyze.hpp, segments.hpp). Their enumerators are numbered so that code()
/// is the byte of a PGM label map and the word the region shader returns
/// (shaders/region_layout.h), with 0 the failing verdict: an all-zero image is
/// "nothing passes", and blank_image starts there.
/// The 8-bit code of a label where bytes leave the program (PGM label maps,
/// the shader's result word): the enumerators' values as documented in
/// docs/region.md (0 none, 1 increasing, ...; with split 0 none, 1 inc-inc, ...).
constexpr std::uint8_t code(Direction label) { return static_cast<std::uint8_t>(label); }
constexpr std::uint8_t code(Split label) { return static_cast<std::uint8_t>(label); }
constexpr std::uint8_t code(Alternation label) { return static_cast<std::uint8_t>(label); }
constexpr std::uint8_t code(EachPiece label) { return static_cast<std::uint8_t>(label); }
inline constexpr std::uint8_t kRegionLabelCodes = 4, kSplitLabelCodes = 6, kAlternatingLabelCodes = 4,
                              kPieceLabelCodes = 3;

/// World rectangle shown by an image: x0 left, x1 right, y0 bottom, y1 top.
struct View {
  double x0 = 0, y0 = 0, x1 = 1, y1 = 1;
};

inline constexpr int kMaxImageSize = 16384;
/// Most pixels one command renders in all (region: images x width x height;
/// sweep: (steps + 1) x width x height): one largest image's worth, 2^28, so
/// that work and memory stay bounded (~1 byte of labels per pixel kept).
inline constexpr long long kMaxTotalPixels = 1LL << 28;

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

/// What to compute. Validated by RegionProblem::make.
struct RegionRequest {
  int point = 0;                 ///< k: the control point placed at each pixel
  std::vector<int> with;         ///< other points moving rigidly with k
  Mode mode = Mode::cmrwi;       ///< cmrwi: monotone; cmr: monotone, no inflection
  std::optional<int> split;      ///< joint s: segments 0..s-1 against s..N-1 (Split results)
  /// Only these segments are judged (prepared and classified); the others,
  /// and the joints at the range's ends, play no part. All when empty.
  std::optional<SegmentRange> segments;
  /// Joints s_1 < ... < s_k inside the judged range: its groups between them
  /// must alternate direction (Alternation results). Not with split.
  std::vector<int> splits;
  /// Each piece on its own (EachPiece results): the groups between `splits`
  /// (every joint of the judged range when empty) must each be monotone, in
  /// either direction, independently. Not with split.
  bool each_piece = false;
  int max_depth = kDefaultDepth; ///< D of Algorithms 1 and 2, 0..kMaxDepth
  int width = 512, height = 512; ///< image size, 1..kMaxImageSize each
  std::optional<View> view;      ///< default_view() when empty
  /// Compute each pixel's decision level (the depth map). Without it, blocks
  /// can be labelled "not monotone" by a proof that skips each pixel's own
  /// traversal (faster), and RegionResult::depth is all zero.
  bool depth = true;
  /// The caller's cancel flag (may be null; the Python module's
  /// KeyboardInterrupt): once it is set, the CPU backend starts no further
  /// block and the image it returns is incomplete, to be dropped.
  const std::atomic<bool>* cancel = nullptr;
};

/// What one position gets. Exactly one of label / split_label /
/// alternating_label is meaningful: split_label when the request has a split,
/// alternating_label when it has splits, label otherwise (the others keep
/// their defaults).
struct RegionPixel {
  Direction label = Direction::none;
  Split split_label = Split::none;
  Alternation alternating_label = Alternation::fail;
  EachPiece piece_label = EachPiece::fail;  ///< with each_piece
  std::uint8_t depth = 0;  ///< deepest level any segment needed
  bool exact = false;      ///< the exact rational path ran
};

/// `pixel` (classified for `request`) is in the region: its label of the
/// request's kind is a certified pass, as RegionResult::in_region reads it.
bool in_region(const RegionPixel& pixel, const RegionRequest& request);
/// The label code of `pixel` of the request's kind (code() of piece_label,
/// alternating_label, split_label or label): what a map rendered for
/// `request` holds at that position (RegionResult::code_at).
std::uint8_t label_code(const RegionPixel& pixel, const RegionRequest& request);

/// A validated, prepared region problem: the exact piece polynomials of the
/// moved segments and the fixed segments' classes, computed once. Cheap to
/// copy (shared immutable state); reusable for many renders and for single
/// positions (contours, editors, sweeps).
class RegionProblem {
 public:
  /// Validates (the only place) and prepares. Throws InputError for a point
  /// out of range, a --with point equal to the moved one or out of range, a
  /// size outside 1..kMaxImageSize, a segment range outside 0..N-1 or
  /// reversed, a split (or one of splits) not strictly inside the judged
  /// range (1..N-1 without one), splits not increasing, split and splits
  /// together, a depth outside 0..kMaxDepth, a view with zero, non-finite or
  /// overflowing extent. Only the judged segments' pieces are prepared.
  static RegionProblem make(const BSpline& spline, const RegionRequest& request);
  /// One problem per point of `points` (request.point is ignored), validated
  /// like make. The spline is analysed once for all of them, and a position's
  /// verdict costs O(degree) whatever the spline's length, so N points cost
  /// O(N), not O(N^2) (`cmr region --point all`).
  static std::vector<RegionProblem> make_each(const BSpline& spline, const RegionRequest& request,
                                              const std::vector<int>& points);

  const BSpline& spline() const;
  /// The request as validated, its view resolved (never empty).
  const RegionRequest& request() const;
  const View& view() const { return *request().view; }
  /// The certified label of one position of the moved point (any p, not only
  /// pixel centres): what every backend gives the pixel centred at p.
  RegionPixel classify(Vec2 position) const;
  /// The prepared state, for backends (the backend interface,
  /// region/region_setup.hpp).
  const backend::RegionSetup& setup() const { return *setup_; }

 private:
  friend class RegionMemo;  // region/region_memo.hpp: problems whose per-span setup is remembered
  explicit RegionProblem(std::shared_ptr<const backend::RegionSetup> setup) : setup_(std::move(setup)) {}
  std::shared_ptr<const backend::RegionSetup> setup_;
};

/// The region semantics stated through analyze(): a position's label is
/// region_label_code(analyze(moved, region_analyze_options(request)), request)
/// for the spline `moved` with the request's point (and group) there. These
/// two are the one mapping from a spline-level analysis to a region label
/// (used where a label is needed for a whole spline that no image holds:
/// the region of weights, region/weight_region.hpp; tests).
/// The analysis options of a request: its depth, mode (split_mode), split or
/// splits and judged segments.
AnalyzeOptions region_analyze_options(const RegionRequest& request);
/// The label code of `analysis` as the request's kind of label, read as the
/// region engine reads it: without split(s) SplineAnalysis::cmrwi, or in CMR
/// mode cmr_algorithm2 (the paper's Algorithm 2); with split or splits the
/// groups' part_verdict over the Algorithm 1/2 classes (analysis.segments)
/// combined by combine_split / alternation_verdict (for SplineAnalysis::split
/// and ::alternation analyze reads inflections exactly, which in CMR mode can
/// be less strict than Algorithm 2).
std::uint8_t region_label_code(const SplineAnalysis& analysis, const RegionRequest& request);

/// A rendered region: row-major, row 0 at the top.
struct RegionResult {
  int width = 0, height = 0;
  View view;
  bool split = false;                    ///< which of the label vectors is filled
  bool alternating = false;              ///< (with splits: alternating_labels)
  bool each_piece = false;               ///< (with each_piece: piece_labels)
  std::vector<Direction> labels;       ///< without split(s), width * height; else empty
  std::vector<Split> split_labels;  ///< with split, width * height; else empty
  std::vector<Alternation> alternating_labels;  ///< with splits, width * height; else empty
  std::vector<EachPiece> piece_labels;  ///< with each_piece, width * height; else empty
  std::vector<std::uint8_t> depth;       ///< decision level per pixel (all 0 without RegionRequest::depth)
  std::uint64_t exact_pixels = 0;        ///< pixels the exact rational path decided
  double seconds = 0;                    ///< wall time of the render
  double setup_seconds = 0;              ///< of which creating device state (shader compilation)

  /// A width x height result with plain labels, every pixel Direction::none
  /// at depth 0 (filled in by a backend, or a picture with no region).
  static RegionResult blank(int width, int height, const View& view);
  std::size_t size() const { return depth.size(); }
  /// The label code of pixel `index` (code() of whichever label it has).
  std::uint8_t code_at(std::size_t index) const {
    return each_piece    ? code(piece_labels[index])
           : alternating ? code(alternating_labels[index])
           : split       ? code(split_labels[index])
                         : code(labels[index]);
  }
  /// Every pixel's label code, as written to PGM label maps.
  std::vector<std::uint8_t> codes() const;
  /// Pixel `index` is in the region: its label is a certified pass
  /// (increasing or decreasing; a split's four directions; inc-first or
  /// dec-first; each-monotone), not a fail and not undecided.
  bool in_region(std::size_t index) const;
  /// How many label codes this result's kind has (kRegionLabelCodes, ...).
  int label_codes() const;
  /// The name of label `code` of this result's kind (to_string of its label):
  /// the key of per-label counts and areas in the JSON.
  const char* label_name(std::uint8_t code) const;
};

/// Where regions are rendered. Every backend gives every pixel the label of
/// RegionProblem::classify at its centre.
class RegionBackend {
 public:
  virtual ~RegionBackend() = default;
  /// Throws BackendError when the backend's environment fails (a device
  /// lost, out of device memory); never for a valid problem otherwise.
  virtual RegionResult render(const RegionProblem& problem) = 0;
  /// "cpu", "vulkan".
  virtual std::string name() const = 0;
};

/// An environment failure of a backend (the CLI's exit code 3): an
/// EnvironmentError (spline/errors.hpp), so callers catch one type.
class BackendError : public EnvironmentError {
 public:
  using EnvironmentError::EnvironmentError;
};

/// All on the host: blocks of pixels decided whole where the certified path
/// holds over the block, quartered down to single pixels elsewhere.
class CpuRegionBackend final : public RegionBackend {
 public:
  /// threads: 0 uses every core.
  explicit CpuRegionBackend(int threads = 0) : threads_(threads) {}
  RegionResult render(const RegionProblem& problem) override;
  std::string name() const override { return "cpu"; }

 private:
  int threads_;
};

}  // namespace cmr
