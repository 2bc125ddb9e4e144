#pragma once
// Internal to cmr::region and the libraries above it: a library user includes
// `region/region.hpp` (space curves: `region/space_region.hpp`).
/// The region of a weight (`cmr region SPLINE --weight K --from A --to B`):
/// with every control point and every other weight fixed, which values of
/// the weight w_K in [A, B] give which region label (the labels of `cmr
/// region`: plain, --split S, --split S1,S2,... alternating; --segments;
/// CMRWI or CMR mode). A polynomial spline is read as all weights 1.
///
/// Derivation. The homogeneous control points are P_i = (w_i x_i, w_i y_i,
/// w_i); only P_K = w_K (x_K, y_K, 1) depends on w_K, linearly. Every span's
/// homogeneous Bezier points are blossoms of the P_i, so H(t) = H0(t) +
/// w_K N(t) Q with Q = (x_K, y_K, 1) and N(t) the K-th basis function's piece:
///  - W, X, Y (and their derivatives) are affine in w_K;
///  - D = det(H, H', H'') is multilinear in three columns that all move along
///    the same vector Q, so every term with two Q columns vanishes: D (and
///    D') is affine in w_K (degree 1);
///  - h = W X' - W' X: the w_K^2 term is N N' x_K - N' N x_K = 0, so h is
///    affine in w_K too;
///  - lambda = (3 W' D + W D')(h.h) - 3 W D (h.h') is then a polynomial of
///    degree at most 2 + 2 = 4 in w_K.
/// The Bernstein coefficients of lambda (8n-11 of them before the degree
/// reduction, 8n-12 after; bezierize/rational_lambda.hpp) and of D, and those
/// of every subdivision piece (linear maps of them), are therefore
/// polynomials of degree <= 4 (lambda) and <= 1 (D) in w_K, and so are the
/// curvature jumps' numerators at joints. Every sign Algorithms 1 and 2 and
/// the joint rules read is the sign of one of finitely many such polynomials
/// (none is identically zero unless it is zero for every w_K), so the label
/// as a function of w_K is piecewise constant with finitely many changes, at
/// roots of those polynomials. (tests/region/weight_region_test.cpp checks the
/// degrees: exact fifth differences of lambda's coefficients and second
/// differences of D's vanish.)
///
/// Algorithm. Nothing is guessed from samples: the label of every weight
/// looked at is the certified label of the whole spline with that weight
/// (region_label_code of analyze(), region/region.hpp: the value every
/// region pixel equals). The interval is sampled at `samples` equally spaced
/// weights (A and B included); where two neighbours differ, the step is
/// bisected (each half whose ends differ, recursively, so a third label met
/// inside is kept) until the bracket is at most `tolerance` * (B - A) wide.
/// The result lists intervals [from, to] whose ends carry the interval's
/// label (certified at both ends), and between two intervals the boundary
/// bracket (to of the first, from of the next): the exact label change lies
/// inside it.
/// Limitation, said plainly: a label that holds only on a stretch narrower
/// than the sampling step (B - A) / (samples - 1), with the same label on
/// both sides (e.g. a single weight where lambda vanishes identically), can
/// be missed; more samples shrink the step.
///
/// Any finite weights are allowed (bspline.hpp), so the interval may reach 0
/// and below: a weight whose spline has a pole (W = 0 somewhere) in a judged
/// span gets analyze's label, 0 (not monotone), and its interval is marked
/// `pole`. Intervals are bisected on the pair (label, pole), so a pole
/// interval's ends are certified like a label's. A single weight where W
/// only touches zero is a stretch of width 0 and can be missed (see above).
/// An interval is refused only where the spline itself is (every weight 0).
#include <cstdint>
#include <string>
#include <vector>

#include "region/region.hpp"
#include "spline/bspline.hpp"

namespace cmr {

/// A copy of `spline` with the weight of control point k set to w (a
/// polynomial spline gets weights 1 elsewhere; on a closed spline k and its
/// twin are one point). InputError from BSpline::make for a weight it
/// refuses (not finite, or every weight 0) and for k outside 0..point_count()-1.
[[nodiscard]] BSpline with_weight(const BSpline& spline, int k, double w);

/// The most samples a weight region takes (each one analyse()s the spline).
inline constexpr int kMaxWeightSamples = 100000;

/// What to compute: an aggregate with defaults.
struct WeightRegionRequest {
  int point = 0;       ///< K: the control point whose weight varies
  double from = 0.5;   ///< A
  double to = 2;       ///< B (A < B, both finite)
  int samples = 257;   ///< equally spaced weights A..B, 2..kMaxWeightSamples
  double tolerance = 1e-9;  ///< boundary brackets at most tolerance * (B - A) wide
  /// The label kind and its verdict: mode, split / splits, segments,
  /// max_depth (point, with, size and view are not used).
  RegionRequest labels;
  int threads = 0;     ///< 0: every core
};

/// A stretch of weights with one label; `from` and `to` have the label.
struct WeightInterval {
  double from = 0, to = 0;
  std::uint8_t label = 0;  ///< code() of the request's kind of label
  bool pole = false;       ///< the spline has a pole in a judged span (then label is 0)
};

/// What one weight gives: its label and whether a judged span has a pole.
struct WeightState {
  std::uint8_t label = 0;
  bool pole = false;
  bool operator==(const WeightState&) const = default;
};

struct WeightRegion {
  std::vector<WeightInterval> intervals;  ///< in order; from of the first is A, to of the last B
  int evaluations = 0;                    ///< labels computed (samples and bisection steps)
  /// The name of a label code of the request's kind (RegionResult::label_name).
  RegionResult kind;
  const char* label_name(std::uint8_t code) const { return kind.label_name(code); }
};

/// Validates (InputError: K out of range; A, B not finite or A >= B; samples
/// outside 2..kMaxWeightSamples; tolerance not in (0, 1); a split or segment
/// range the spline lacks; a weight A or B the spline refuses) and computes.
WeightRegion weight_region(const BSpline& spline, const WeightRegionRequest& request);

/// The label and pole flag of the spline with w_K = w: what weight_region bisects.
WeightState weight_state(const BSpline& spline, const WeightRegionRequest& request, double w);
/// The label code of the spline with w_K = w.
std::uint8_t weight_label(const BSpline& spline, const WeightRegionRequest& request, double w);

}  // namespace cmr
