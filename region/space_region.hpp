#pragma once
// Regions of a point of a space curve moving in a plane (issue 25):
// control point K placed at Q(a, b) = O + a U + b V for every pixel (a, b) of
// a view of the plane's coordinates, labelled with the spline-level curvature
// verdict of analyze_space (bezierize/space_analyze.hpp) for the spline so
// changed.
//
// Semantics of one position (a, b): Q is the exact point O + a U + b V
// (exact rationals from the doubles O, U, V, a, b; it need not be a double),
// and the label is the verdict exact arithmetic gives for the spline with
// point K (and its twin on a closed spline) at Q: increasing / decreasing
// (|kappa| monotone over the whole spline), none (not monotone), or undecided at the
// depth limit. Pixel centres are those of the plane (region.hpp:
// pixel_center). Certification: each affected segment's lambda3 is computed
// with error bounds from Q's error-bounded coordinates, and exactly (GMP)
// where a sign that matters is uncertain; joints whose jump matters (not C^2
// by the knots) likewise. Segments and joints that K does not touch are
// classified once. Every Bernstein coefficient of lambda3 is a bivariate
// quartic in (a, b) (c is affine in Q); this backend evaluates it per pixel
// rather than as a prepared polynomial (the plane's RegionSetup), so it is
// slower than the planar engine; vk/space_region_vk.hpp is the device backend.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "region/region.hpp"
#include "bezierize/space_analyze.hpp"

namespace cmr {

struct SpacePlane {
  Vec3 origin{0.0}, u{1, 0, 0}, v{0, 1, 0};
};

/// A plane from its text: "xy", "yz" or "zx" (the coordinate plane through
/// `through`, axes in that order), or nine numbers "ox,oy,oz,ux,uy,uz,vx,vy,vz".
/// InputError for anything else, a non-finite number, or U, V parallel or zero
/// ("plane: U and V are parallel (the plane is degenerate)", plane a field).
SpacePlane parse_space_plane(const std::string& text, Vec3 through);
/// The default plane of point k: through P_k, spanned by the directions to its
/// neighbours (P_{k+1} - P_k and P_{k-1} - P_k; at an end, the next two
/// points). InputError when they are parallel.
SpacePlane default_space_plane(const SpaceSpline& spline, int k);

/// SpaceRegionRequest::time_limit's default (seconds per render).
inline constexpr double kDefaultSpaceRegionSeconds = 60;

struct SpaceRegionRequest {
  int point = 0;
  std::optional<SpacePlane> plane;  ///< default_space_plane when empty
  int max_depth = kDefaultDepth;
  int width = 256, height = 256;
  std::optional<View> view;  ///< in plane coordinates (a, b); default: the projected polygon with a margin
  bool exact_only = false;   ///< skip the error-bounded path (tests: the exact reference)
  /// Seconds one render may take (0: no limit). Pixels the error bounds
  /// cannot decide go to exact (GMP) arithmetic, which extreme weights
  /// (1e300 and 1e-300) make ~9 ms a pixel: render() stops with InputError
  /// once past this, or after its first second when the pixels so far
  /// project to more than 4 times it.
  double time_limit = kDefaultSpaceRegionSeconds;
};

/// The planar spline of the control points' plane coordinates (least
/// squares, exact for points in the plane): the curve as seen in the plane,
/// for pictures and the default view.
BSpline project_to_plane(const SpaceSpline& spline, const SpacePlane& plane);

class SpaceRegionProblem {
 public:
  /// Validates: point in range, plane finite and not degenerate, size
  /// 1..kMaxImageSize, depth 0..kMaxDepth, view finite with positive extent.
  static SpaceRegionProblem make(const SpaceSpline& spline, const SpaceRegionRequest& request);
  const SpaceRegionRequest& request() const;  ///< plane and view resolved
  const SpaceSpline& spline() const;
  /// The certified label of position (a, b).
  RegionPixel classify(double a, double b) const;
  /// Every pixel (threads: 0 = all cores); labels are Direction.
  RegionResult render(int threads = 0) const;

  // For device backends (vk/space_region_vk.hpp), which judge the parts a
  // pixel's label depends on and leave the fold to compose():
  /// The segments whose window holds the moved point (or its twin), ascending.
  const std::vector<int>& moved_segments() const;
  /// The joints (1..N; N: a closed spline's seam) next to a moved segment and
  /// not C^2 by the knots, whose curvature jump varies with the point.
  const std::vector<int>& moved_joints() const;
  /// Bezier point k of segment `segment` as F_k + m_k Q for the moved point
  /// Q (exact from the knots and the fixed points): 4 (d+1) entries
  /// F_k.x, F_k.y, F_k.z, m_k, each (nearest double, bound on the rounding).
  std::vector<std::array<double, 2>> affine_bezier(int segment) const;
  /// The pixel from the certified classes of the moved segments (in
  /// moved_segments() order) and the exact jump signs of the moved joints
  /// (moved_joints() order): classify's fold, so the same label and depth.
  RegionPixel compose(const std::vector<MonotonicityResult>& moved, const std::vector<int>& jumps) const;

  // For device backends on rational curves: the pixel-dependent quantities
  // as polynomials in the offsets (x, y) = (a - a0, b - b0) of the plane
  // coordinates from a base point (a0, b0). The moved homogeneous point
  // (w Q, w) is affine in (x, y), and so are e (3x3 minors of [H H' H''],
  // multilinear with Q in at most one column) and h = W X' - W' X; E, G are
  // quadratic, W affine, so each lambda3 coefficient has degree 5. Exact:
  // interpolated in rationals on a grid and checked to vanish above the degree.
  /// Terms x^p y^q, p + q <= degree, ordered p = 0..degree, q = 0..degree-p;
  /// each (nearest double, bound on its rounding) of the exact coefficient.
  struct PlanePolynomial {
    int degree = 0;
    std::vector<std::array<double, 2>> terms;
  };
  /// Rational curves: a moved segment's lambda3 Bernstein coefficients
  /// (classify's, 11n-17 of them), each of degree 5 in (x, y).
  std::vector<PlanePolynomial> rational_lambda3(int segment, double a0, double b0) const;
  /// Rational curves: joint j's (moved_joints()) gl, gr (degree 2) and D
  /// (degree 8) of classify's rule: the jump's sign is sign(D) where gl, gr > 0.
  std::array<PlanePolynomial, 3> rational_jump(int joint, double a0, double b0) const;

 private:
  struct State;
  explicit SpaceRegionProblem(std::shared_ptr<const State> s) : state_(std::move(s)) {}
  template <bool kRational>
  RegionPixel classify_as(double a, double b) const;
  std::shared_ptr<const State> state_;
};

/// Where space regions are rendered: RegionBackend's interface (region.hpp)
/// for space curves. Every backend gives every pixel the label of
/// SpaceRegionProblem::classify at its centre. make_space_region_backend
/// (vk/backend_choice.hpp) builds one from the same BackendChoice as the
/// planar backends.
class SpaceRegionBackend {
 public:
  virtual ~SpaceRegionBackend() = default;
  /// Throws InputError for a problem this backend cannot take or a render
  /// over its time limit, EnvironmentError when its environment fails.
  virtual RegionResult render(const SpaceRegionProblem& problem) = 0;
  /// "cpu", "vulkan".
  virtual std::string name() const = 0;
  /// Of the last render, the pixels a device left to the CPU (it could not
  /// certify them); nullopt for a backend that renders on the CPU alone.
  virtual std::optional<std::size_t> host_pixels() const { return std::nullopt; }
};

/// All on the host: SpaceRegionProblem::render.
class CpuSpaceRegionBackend final : public SpaceRegionBackend {
 public:
  /// threads: 0 uses every core.
  explicit CpuSpaceRegionBackend(int threads = 0) : threads_(threads) {}
  RegionResult render(const SpaceRegionProblem& problem) override { return problem.render(threads_); }
  std::string name() const override { return "cpu"; }

 private:
  int threads_;
};

}  // namespace cmr
