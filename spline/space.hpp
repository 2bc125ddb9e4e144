#pragma once
// Space curves (issue 25): polynomial B-splines in R^3, beside the planar
// BSpline, which stays untouched.
//
// A SpaceSpline is a planar BSpline of the points' (x, y) (its "shadow":
// knots, degree, segments, closed form and every validation are the plane's,
// once, by BSpline::make / make_closed) plus the z coordinates. The blossom
// (spline/blossom.hpp) is generic over the point type, so evaluation,
// derivatives and Bezier extraction run on glm::dvec3 with the same code.
//
// Rational space curves: optional positive weights w_i, one per control
// point, make the curve C = X / W with the homogeneous B-spline
// H(t) = (X, W) = sum_i N_i(t) (w_i P_i, w_i) in R^4. The shadow then carries
// the weights too (its checks and messages: count, finiteness; equal weights
// are dropped, the same polynomial curve), and the homogeneous points are
// blossomed like any others. Weights must be positive (so W > 0 on the whole
// curve: no poles); a weight <= 0 is an InputError naming it.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <nlohmann/json_fwd.hpp>

#include "spline/bspline.hpp"
#include "spline/spline_json.hpp"

namespace cmr {

using Vec3 = glm::dvec3;
using Vec4 = glm::dvec4;

/// A homogeneous space point (w x, w y, w z, w) for non-double scalars
/// (Bounded, Rational); HPoint3<double> is glm::dvec4.
template <class T>
struct Vec4T {
  T x{}, y{}, z{}, w{};
  Vec4T() = default;
  Vec4T(T x_, T y_, T z_, T w_) : x(std::move(x_)), y(std::move(y_)), z(std::move(z_)), w(std::move(w_)) {}
  friend Vec4T operator+(const Vec4T& a, const Vec4T& b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
  friend Vec4T operator-(const Vec4T& a, const Vec4T& b) { return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w}; }
  friend Vec4T operator*(const T& s, const Vec4T& a) { return {s * a.x, s * a.y, s * a.z, s * a.w}; }
};
template <class T>
struct HPoint3Of {
  using type = Vec4T<T>;
};
template <>
struct HPoint3Of<double> {
  using type = Vec4;
};
template <class T>
using HPoint3 = typename HPoint3Of<T>::type;

class SpaceSpline {
 public:
  /// As BSpline::make (same knot rules and messages), with 3D points; a
  /// non-finite coordinate is an InputError naming it ("points[2][2] is not a
  /// finite number").
  /// `weights`: empty (polynomial) or one positive finite weight per point
  /// ("weights[1] is 0: rational space curves need positive weights").
  static SpaceSpline make(int degree, std::vector<double> knots, std::vector<Vec3> points, std::string name = {},
                          std::vector<double> weights = {});
  /// The Bezier curve of degree points.size()-1.
  static SpaceSpline bezier(std::vector<Vec3> points, std::string name = {}, std::vector<double> weights = {});
  /// As BSpline::make_closed: m distinct points, the m+1 knots of one period.
  static SpaceSpline make_closed(int degree, std::vector<double> knots, std::vector<Vec3> points,
                                 std::string name = {}, std::vector<double> weights = {});
  /// A planar spline placed in the plane z = 0 (InputError for a rational one
  /// with a weight <= 0).
  static SpaceSpline embed(const BSpline& planar);

  int degree() const { return shadow_.degree(); }
  const std::vector<double>& knots() const { return shadow_.knots(); }
  /// The control points (unrolled for a closed spline, as BSpline::points()).
  const std::vector<Vec3>& points() const { return points_; }
  const std::string& name() const { return shadow_.name(); }
  int point_count() const { return static_cast<int>(points_.size()); }
  int unique_point_count() const { return shadow_.unique_point_count(); }
  const std::vector<Segment>& segments() const { return shadow_.segments(); }
  int segment_count() const { return shadow_.segment_count(); }
  double domain_begin() const { return shadow_.domain_begin(); }
  double domain_end() const { return shadow_.domain_end(); }
  const Segment& segment_at(double t) const { return shadow_.segment_at(t); }
  int multiplicity(double u) const { return shadow_.multiplicity(u); }
  bool closed() const { return shadow_.closed(); }
  std::vector<double> period_knots() const { return shadow_.period_knots(); }
  int twin(int k) const { return shadow_.twin(k); }
  /// The planar spline of the points' (x, y) (and the weights): the knot structure.
  const BSpline& shadow() const { return shadow_; }
  /// Whether the curve is rational (weights that are not all equal).
  bool is_rational() const { return shadow_.is_rational(); }
  /// The weights, one per (unrolled) point; empty for a polynomial curve.
  const std::vector<double>& weights() const { return shadow_.weights(); }
  double weight(int i) const { return shadow_.weight(i); }
  /// (w x, w y, w z, w) per (unrolled) point; (x, y, z, 1) for a polynomial curve.
  const std::vector<Vec4>& homogeneous_points() const { return hpoints_; }

  /// A copy with control point k (and its twin on a closed spline) replaced;
  /// InputError for a non-finite point.
  [[nodiscard]] SpaceSpline with_point(int k, Vec3 p) const;

 private:
  SpaceSpline(BSpline shadow, std::vector<Vec3> points);
  static SpaceSpline from_shadow(BSpline shadow, const std::vector<double>& z);
  friend SpaceSpline space_spline_from_json(const nlohmann::json& doc, const ReadOptions& options);
  BSpline shadow_;
  std::vector<Vec3> points_;
  std::vector<Vec4> hpoints_;
};

/// f(args[0..d-1]) on segment s (the polynomial blossom: CMR_CHECK that the
/// spline is not rational; use homogeneous_blossom).
Vec3 blossom(const SpaceSpline& spline, const Segment& s, const double* args);
/// The homogeneous blossom (w x, w y, w z, w) on segment s; (x, y, z, 1) for
/// a polynomial curve.
Vec4 homogeneous_blossom(const SpaceSpline& spline, const Segment& s, const double* args);
/// C(t) (projected for a rational curve).
Vec3 evaluate(const SpaceSpline& spline, double t);
/// C^(r)(t), 0 <= r <= d; for a rational curve by Leibniz' rule on H = W C:
/// C^(r) = (X^(r) - sum_{i=1..r} C(r,i) W^(i) C^(r-i)) / W.
Vec3 derivative(const SpaceSpline& spline, double t, int r);
/// The d+1 Bezier points of segment s (double; for a rational curve the
/// projections of the homogeneous ones, i.e. the rational Bezier control
/// points; the exact ones: space_analyze.hpp).
std::vector<Vec3> bezier_points(const SpaceSpline& spline, const Segment& s);
/// The d+1 homogeneous Bezier points of segment s.
std::vector<Vec4> homogeneous_bezier_points(const SpaceSpline& spline, const Segment& s);
/// Curvature |C' x C''| / |C'|^3 and torsion det(C', C'', C''') / |C' x C''|^2
/// at t, in double (for plots and tests; certified decisions never use them).
double space_curvature(const SpaceSpline& spline, double t);
double space_torsion(const SpaceSpline& spline, double t);

/// 2 when every point of the file's "points" is [x, y] (or there are none or
/// they are malformed: the planar reader then reports it), 3 when every one
/// is [x, y, z]. Mixed counts are an InputError naming both points:
/// "points[1] has 3 coordinates but points[0] has 2 (all points must be
/// [x, y], or all [x, y, z])".
int spline_dimension(const nlohmann::json& doc);
/// The dimension of a spline file (spline_dimension of its JSON, prefixed
/// with the path on error). A file that is not a JSON object counts as 2
/// (the planar reader then reports it).
int spline_file_dimension(const std::filesystem::path& path);
/// The same of the file's document, already parsed (read_spline_document).
int spline_file_dimension(const std::filesystem::path& path, const nlohmann::json& doc);

/// A spline file with [x, y, z] points: the planar file format (spline_json.hpp)
/// otherwise, every field and message the same ("weights" included, which
/// must moreover be positive).
SpaceSpline space_spline_from_json(const nlohmann::json& doc, const ReadOptions& options = {});
SpaceSpline read_space_spline_file(const std::filesystem::path& path, const ReadOptions& options = {});
nlohmann::json space_spline_to_json(const SpaceSpline& spline);

}  // namespace cmr
