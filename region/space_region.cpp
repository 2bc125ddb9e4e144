#include "region/space_region.hpp"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>

#include <glm/geometric.hpp>

#include "numeric/roots.hpp"
#include "bezierize/space_classify.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/parallel.hpp"

namespace cmr {

namespace {

bool finite3(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

/// U x V == 0 exactly (parallel or zero directions).
bool degenerate(const Vec3& u, const Vec3& v) {
  const Point3<Rational> a{Rational(u.x), Rational(u.y), Rational(u.z)}, b{Rational(v.x), Rational(v.y), Rational(v.z)};
  const Point3<Rational> c = cross3(a, b);
  return sgn(c.x) == 0 && sgn(c.y) == 0 && sgn(c.z) == 0;
}

void check_plane(const SpacePlane& p, const std::string& what) {
  if (!finite3(p.origin) || !finite3(p.u) || !finite3(p.v)) throw InputFieldError(what + ": not finite");
  if (degenerate(p.u, p.v)) throw InputFieldError(what + ": U and V are parallel (the plane is degenerate)");
}

}  // namespace

SpacePlane parse_space_plane(const std::string& text, Vec3 through) {
  if (text == "xy") return {through, {1, 0, 0}, {0, 1, 0}};
  if (text == "yz") return {through, {0, 1, 0}, {0, 0, 1}};
  if (text == "zx") return {through, {0, 0, 1}, {1, 0, 0}};
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double x = 0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size())
      throw InputFieldError(field("plane") + ": '" + item +
                            "' is not a number (expected xy, yz, zx or OX,OY,OZ,UX,UY,UZ,VX,VY,VZ)");
    v.push_back(x);
  }
  if (v.size() != 9)
    throw InputFieldError(field("plane") + ": " + std::to_string(v.size()) +
                          " numbers given, expected 9 (OX,OY,OZ,UX,UY,UZ,VX,VY,VZ), or xy, yz, zx");
  SpacePlane p{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}};
  check_plane(p, field("plane"));
  return p;
}

SpacePlane default_space_plane(const SpaceSpline& spline, int k) {
  const int m = spline.unique_point_count();
  if (k < 0 || k >= m)
    throw InputFieldError(field("point") + " " + std::to_string(k) + " is outside 0.." + std::to_string(m - 1));
  const auto P = [&](int i) { return spline.points()[static_cast<std::size_t>(i)]; };
  int i1 = k + 1, i2 = k - 1;
  if (spline.closed()) {
    i1 = (k + 1) % m;
    i2 = (k + m - 1) % m;
  } else if (k == 0) {
    i2 = 2;
  } else if (k == m - 1) {
    i1 = m - 3;
  }
  if (i1 < 0 || i2 < 0 || i1 >= m || i2 >= m)
    throw InputFieldError("point " + std::to_string(k) + " has too few neighbours for a default plane; give " +
                          field("plane"));
  SpacePlane p{P(k), P(i1) - P(k), P(i2) - P(k)};
  if (degenerate(p.u, p.v))
    throw InputFieldError("the default plane of point " + std::to_string(k) +
                          " is degenerate (its neighbours are collinear with it); give " + field("plane"));
  return p;
}

BSpline project_to_plane(const SpaceSpline& spline, const SpacePlane& plane) {
  const double uu = glm::dot(plane.u, plane.u), uv = glm::dot(plane.u, plane.v), vv = glm::dot(plane.v, plane.v);
  const double det = uu * vv - uv * uv;
  std::vector<Vec2> pts;
  for (int k = 0; k < spline.unique_point_count(); ++k) {
    const Vec3 x = spline.points()[static_cast<std::size_t>(k)] - plane.origin;
    const double bu = glm::dot(plane.u, x), bv = glm::dot(plane.v, x);
    pts.emplace_back((vv * bu - uv * bv) / det, (uu * bv - uv * bu) / det);
  }
  std::vector<double> w(spline.weights().begin(), spline.weights().begin() + (spline.is_rational() ? pts.size() : 0));
  if (spline.closed()) return BSpline::make_closed(spline.degree(), spline.period_knots(), pts, spline.name(), w);
  return BSpline::make(spline.degree(), spline.knots(), pts, spline.name(), w);
}

struct SpaceRegionProblem::State {
  SpaceSpline spline;
  SpaceRegionRequest request;
  std::vector<SpaceSegmentResult> segments;
  std::vector<SpaceJoint> joints;
  std::optional<SpaceJoint> seam;
  std::vector<int> moved_segments;  ///< segments whose window holds the point (or its twin)
  std::vector<int> moved_joints;    ///< joint indices 1..N (N: the seam) next to a moved segment, not C^2
};

namespace {

template <class T>
std::vector<Point3<T>> moved_window(const SpaceSpline& spline, const SpaceWindow& w, int k, int twin,
                                    const Point3<T>& q) {
  std::vector<Point3<T>> pts = space_window_points<T>(spline, w);
  for (int i = 0; i <= w.degree; ++i)
    if (w.first + i == k || w.first + i == twin) pts[static_cast<std::size_t>(i)] = q;
  return pts;
}

/// A rational spline's window with point k (weight kept) at q: (w q, w).
template <class T>
std::vector<HPoint3<T>> moved_hwindow(const SpaceSpline& spline, const SpaceWindow& w, int k, int twin,
                                      const Point3<T>& q) {
  std::vector<HPoint3<T>> pts = space_window_hpoints<T>(spline, w);
  for (int i = 0; i <= w.degree; ++i)
    if (w.first + i == k || w.first + i == twin)
      pts[static_cast<std::size_t>(i)] = to_hpoint3<T>(q, spline.weight(w.first + i));
  return pts;
}

/// sign(kappa_R - kappa_L) from the Bezier points (and weights, empty for a
/// polynomial spline) of the two sides, space_analyze.cpp's rule with
/// kappa^2 = f^2 (w0 w2 / w1^2)^2 |a x b|^2 / |a|^6 multiplied out
/// (weights > 0): kSignUnknown when T's bounds do not decide.
/// The quantities of jump_sign3: the squared leg lengths gl, gr at the
/// joint and d, whose sign is the jump's where gl, gr > 0.
template <class T>
struct JumpTerms {
  T gl, gr, d;
};
template <class T>
JumpTerms<T> jump_terms3(const std::vector<Point3<T>>& L, const std::vector<T>& wl, const std::vector<Point3<T>>& R,
                         const std::vector<T>& wr) {
  const int d = static_cast<int>(L.size()) - 1;
  const Point3<T> al = L[d - 1] - L[d], bl = L[d - 2] - L[d - 1], ar = R[1] - R[0], br = R[2] - R[1];
  const T gl = dot3(al, al), gr = dot3(ar, ar);
  const Point3<T> xl = cross3(al, bl), xr = cross3(ar, br);
  T a2l = dot3(xl, xl), a2r = dot3(xr, xr);
  if (!wl.empty()) {
    // (w0 w2)^2 w1'^4 on the other side's w1' clears both denominators.
    const T ol = wl[d] * wl[d - 2], orr = wr[0] * wr[2], l1 = wl[d - 1] * wl[d - 1], r1 = wr[1] * wr[1];
    a2l = T(a2l * ol * ol * r1 * r1);
    a2r = T(a2r * orr * orr * l1 * l1);
  }
  return {gl, gr, T(T(a2r * gl * gl * gl) - T(a2l * gr * gr * gr))};
}
template <class T>
JumpTerms<T> jump_terms3(const std::vector<HPoint3<T>>& HL, const std::vector<HPoint3<T>>& HR) {
  std::vector<Point3<T>> L, R;
  std::vector<T> wl, wr;
  split_homogeneous<T>(HL, L, wl);
  split_homogeneous<T>(HR, R, wr);
  return jump_terms3<T>(L, wl, R, wr);
}

template <class T>
int jump_sign3(const JumpTerms<T>& t) {
  const int sl = Scalar<T>::sign(t.gl), sr = Scalar<T>::sign(t.gr);
  if (sl == kSignUnknown || sr == kSignUnknown) return kSignUnknown;
  if (sl == 0 || sr == 0) return 0;
  return Scalar<T>::sign(t.d);
}
template <class T>
int jump_sign3(const std::vector<Point3<T>>& L, const std::vector<Point3<T>>& R) {
  return jump_sign3<T>(jump_terms3<T>(L, {}, R, {}));
}
template <class T>
int jump_sign3(const std::vector<HPoint3<T>>& HL, const std::vector<HPoint3<T>>& HR) {
  return jump_sign3<T>(jump_terms3<T>(HL, HR));
}

/// (nearest double, bound on the rounding) of r.
std::array<double, 2> rounded_with_bound(const Rational& r) {
  const double v = nearest_double(r);
  const Rational e = abs(Rational(r - Rational(v)));
  const double eb = e.get_d();
  return {v, sgn(e) == 0 ? 0.0 : std::nextafter(eb, std::numeric_limits<double>::infinity()) * (1 + 0x1p-50)};
}

/// The polynomials of total degree `degree` in (x, y) through values(x, y)
/// (each call: `count` exact values) on the grid x, y in 0..degree: tensor
/// Lagrange interpolation in rationals, then a check that every term above
/// the degree vanishes (so the values are such polynomials on the grid).
template <class Values>
std::vector<SpaceRegionProblem::PlanePolynomial> interpolate_plane(int degree, std::size_t count, Values values) {
  using Matrix = std::vector<std::vector<Rational>>;
  const std::size_t n = static_cast<std::size_t>(degree) + 1;
  // basis[i][p]: the coefficient of t^p in the Lagrange polynomial of node i.
  Matrix basis(n, std::vector<Rational>(n));
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<Rational> c(1, Rational(1));
    Rational den(1);
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      std::vector<Rational> next(c.size() + 1, Rational(0));  // c * (t - j)
      for (std::size_t k = 0; k < c.size(); ++k) {
        next[k + 1] += c[k];
        next[k] -= c[k] * Rational(static_cast<long>(j));
      }
      c = std::move(next);
      den *= static_cast<long>(i) - static_cast<long>(j);
    }
    for (std::size_t p = 0; p < n; ++p) basis[i][p] = c[p] / den;
  }
  // grid[i][j]: the values at (i, j).
  std::vector<std::vector<std::vector<Rational>>> grid(n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      std::vector<Rational> v = values(Rational(static_cast<long>(i)), Rational(static_cast<long>(j)));
      CMR_CHECK(v.size() == count);
      grid[i].push_back(std::move(v));
    }
  std::vector<SpaceRegionProblem::PlanePolynomial> out(count);
  for (std::size_t k = 0; k < count; ++k) {
    // A[p][j] = sum_i basis[i][p] v(i, j); C[p][q] = sum_j basis[j][q] A[p][j].
    Matrix A(n, std::vector<Rational>(n)), C(n, std::vector<Rational>(n));
    for (std::size_t p = 0; p < n; ++p)
      for (std::size_t j = 0; j < n; ++j)
        for (std::size_t i = 0; i < n; ++i) A[p][j] += basis[i][p] * grid[i][j][k];
    for (std::size_t p = 0; p < n; ++p)
      for (std::size_t q = 0; q < n; ++q) {
        for (std::size_t j = 0; j < n; ++j) C[p][q] += basis[j][q] * A[p][j];
        CMR_CHECK(p + q < n || sgn(C[p][q]) == 0);  // the degree bound holds
      }
    out[k].degree = degree;
    for (std::size_t p = 0; p < n; ++p)
      for (std::size_t q = 0; p + q < n; ++q) out[k].terms.push_back(rounded_with_bound(C[p][q]));
  }
  return out;
}

/// p (of higher nominal degree) as a polynomial of degree `degree`: its
/// terms above it must be zero.
SpaceRegionProblem::PlanePolynomial lowered(const SpaceRegionProblem::PlanePolynomial& p, int degree) {
  SpaceRegionProblem::PlanePolynomial out;
  out.degree = degree;
  std::size_t t = 0;
  for (int i = 0; i <= p.degree; ++i)
    for (int j = 0; i + j <= p.degree; ++j, ++t) {
      if (i + j <= degree) out.terms.push_back(p.terms[t]);
      else CMR_CHECK(p.terms[t][0] == 0 && p.terms[t][1] == 0);
    }
  return out;
}

/// The label and depth of a pixel from its segments' classes and joints.
RegionPixel fold_pixel(const SpaceSpline& spline, const std::vector<SpaceSegmentResult>& segs,
                       const std::vector<SpaceJoint>& joints, const std::optional<SpaceJoint>& seam) {
  RegionPixel px;
  px.label = space_verdict(spline, segs, joints, seam, false);
  int depth = 0;
  bool level0 = false;
  for (const SpaceSegmentResult& r : segs) {
    depth = std::max(depth, r.curvature.depth);
    level0 = level0 || (r.curvature.curvature == Curvature::non_monotone && r.curvature.depth == 0);
  }
  px.depth = static_cast<std::uint8_t>(level0 ? 0 : depth);
  return px;
}

}  // namespace

SpaceRegionProblem SpaceRegionProblem::make(const SpaceSpline& spline, const SpaceRegionRequest& request) {
  auto s = std::make_shared<State>(State{spline, request, {}, {}, {}, {}, {}});
  SpaceRegionRequest& r = s->request;
  const int m = spline.unique_point_count();
  if (r.point < 0 || r.point >= m)
    throw InputFieldError(field("point") + " " + std::to_string(r.point) + " is outside 0.." + std::to_string(m - 1));
  if (r.max_depth < 0 || r.max_depth > kMaxDepth)
    throw InputFieldError(field("max_depth") + " " + std::to_string(r.max_depth) + " is outside 0.." +
                          std::to_string(kMaxDepth));
  if (r.width < 1 || r.width > kMaxImageSize || r.height < 1 || r.height > kMaxImageSize)
    throw InputFieldError(field("size") + " " + std::to_string(r.width) + "x" + std::to_string(r.height) +
                          " is outside 1.." + std::to_string(kMaxImageSize) + " per side");
  if (!(r.time_limit >= 0) || !std::isfinite(r.time_limit))
    throw InputError("space region: time limit " + std::to_string(r.time_limit) + " is not a number of seconds >= 0");
  if (!r.plane) r.plane = default_space_plane(spline, r.point);
  check_plane(*r.plane, field("plane"));
  if (!r.view) r.view = default_view(project_to_plane(spline, *r.plane), r.width, r.height);
  const View& v = *r.view;
  if (!std::isfinite(v.x0) || !std::isfinite(v.x1) || !std::isfinite(v.y0) || !std::isfinite(v.y1) ||
      !(v.x1 > v.x0) || !(v.y1 > v.y0) || !std::isfinite(v.x1 - v.x0) || !std::isfinite(v.y1 - v.y0))
    throw InputFieldError(field("view") + ": needs finite X0 < X1 and Y0 < Y1");
  SpaceAnalyzeOptions o;
  o.max_depth = r.max_depth;
  for (const Segment& seg : spline.segments()) s->segments.push_back(space_segment(spline, seg, o));
  const int N = spline.segment_count(), d = spline.degree();
  for (int i = 1; i < N; ++i) s->joints.push_back(space_joint(spline, i - 1, i, o.continuity));
  if (spline.closed()) s->seam = space_joint(spline, N - 1, 0, o.continuity);
  const int twin = spline.twin(r.point);
  std::vector<bool> moved(static_cast<std::size_t>(N), false);
  for (const Segment& seg : spline.segments()) {
    const int first = seg.span - d + 1;
    for (int i = first; i <= first + d; ++i) moved[seg.index] = moved[seg.index] || i == r.point || i == twin;
    if (moved[seg.index]) s->moved_segments.push_back(seg.index);
  }
  for (int i = 1; i <= N; ++i) {
    if (i == N && !spline.closed()) break;
    const int left = i - 1, right = i % N;
    const SpaceJoint& j = i == N ? *s->seam : s->joints[i - 1];
    if ((moved[left] || moved[right]) && j.continuity < 2) s->moved_joints.push_back(i);
  }
  return SpaceRegionProblem(std::move(s));
}

const SpaceRegionRequest& SpaceRegionProblem::request() const { return state_->request; }
const SpaceSpline& SpaceRegionProblem::spline() const { return state_->spline; }

RegionPixel SpaceRegionProblem::classify(double a, double b) const {
  return state_->spline.is_rational() ? classify_as<true>(a, b) : classify_as<false>(a, b);
}

template <bool kRational>
RegionPixel SpaceRegionProblem::classify_as(double a, double b) const {
  const State& s = *state_;
  const SpacePlane& pl = *s.request.plane;
  const int k = s.request.point, twin = s.spline.twin(k);
  // The window with point k (and its twin) at q: Cartesian points, or
  // homogeneous ones (the point's weight kept) for a rational spline.
  const auto moved = [&](const SpaceWindow& w, const auto& q) {
    using T = std::remove_cvref_t<decltype(q.x)>;
    if constexpr (kRational) return moved_hwindow<T>(s.spline, w, k, twin, q);
    else return moved_window<T>(s.spline, w, k, twin, q);
  };
  const auto coord_b = [&](double o, double u, double v) { return Bounded(o) + Bounded(a) * Bounded(u) + Bounded(b) * Bounded(v); };
  const auto coord_r = [&](double o, double u, double v) {
    return Rational(Rational(o) + Rational(a) * Rational(u) + Rational(b) * Rational(v));
  };
  const Point3<Bounded> qb{coord_b(pl.origin.x, pl.u.x, pl.v.x), coord_b(pl.origin.y, pl.u.y, pl.v.y),
                           coord_b(pl.origin.z, pl.u.z, pl.v.z)};
  std::optional<Point3<Rational>> qr;
  const auto exact_q = [&]() -> const Point3<Rational>& {
    if (!qr) qr = Point3<Rational>{coord_r(pl.origin.x, pl.u.x, pl.v.x), coord_r(pl.origin.y, pl.u.y, pl.v.y),
                                   coord_r(pl.origin.z, pl.u.z, pl.v.z)};
    return *qr;
  };
  RegionPixel px;
  std::vector<SpaceSegmentResult> segs = s.segments;
  for (const int i : s.moved_segments) {
    const SpaceWindow w = space_window(s.spline, s.spline.segments()[static_cast<std::size_t>(i)]);
    const auto make_b = [&] { return moved(w, qb); };
    const auto make_r = [&] { return moved(w, exact_q()); };
    SpaceDecision dec;
    if (s.request.exact_only) {
      const auto r = algorithm1(lambda3_bernstein<Rational>(space_window_bezier<Rational>(w, make_r())), s.request.max_depth);
      CMR_CHECK(r.has_value());
      dec.result = *r;
      dec.exact_used = true;
    } else {
      dec = space_decide(w, SpaceQuantity::curvature, s.request.max_depth, make_b, make_r);
    }
    segs[static_cast<std::size_t>(i)].curvature = dec.result;
    px.exact = px.exact || dec.exact_used;
  }
  std::vector<SpaceJoint> joints = s.joints;
  std::optional<SpaceJoint> seam = s.seam;
  const int N = s.spline.segment_count();
  for (const int i : s.moved_joints) {
    const Segment& L = s.spline.segments()[static_cast<std::size_t>(i - 1)];
    const Segment& R = s.spline.segments()[static_cast<std::size_t>(i % N)];
    const SpaceWindow wl = space_window(s.spline, L), wr = space_window(s.spline, R);
    int sign = kSignUnknown;
    if (!s.request.exact_only)
      sign = jump_sign3<Bounded>(space_window_bezier<Bounded>(wl, moved(wl, qb)),
                                 space_window_bezier<Bounded>(wr, moved(wr, qb)));
    if (sign == kSignUnknown) {
      sign = jump_sign3<Rational>(
          space_window_bezier<Rational>(wl, moved(wl, exact_q())),
          space_window_bezier<Rational>(wr, moved(wr, exact_q())));
      px.exact = true;
    }
    (i == N ? *seam : joints[static_cast<std::size_t>(i - 1)]).jump = sign;
  }
  const RegionPixel folded = fold_pixel(s.spline, segs, joints, seam);
  px.label = folded.label;
  px.depth = folded.depth;
  return px;
}

const std::vector<int>& SpaceRegionProblem::moved_segments() const { return state_->moved_segments; }
const std::vector<int>& SpaceRegionProblem::moved_joints() const { return state_->moved_joints; }

RegionPixel SpaceRegionProblem::compose(const std::vector<MonotonicityResult>& moved, const std::vector<int>& jumps) const {
  const State& s = *state_;
  CMR_CHECK(moved.size() == s.moved_segments.size() && jumps.size() == s.moved_joints.size());
  std::vector<SpaceSegmentResult> segs = s.segments;
  for (std::size_t i = 0; i < moved.size(); ++i) segs[static_cast<std::size_t>(s.moved_segments[i])].curvature = moved[i];
  std::vector<SpaceJoint> joints = s.joints;
  std::optional<SpaceJoint> seam = s.seam;
  const int N = s.spline.segment_count();
  for (std::size_t i = 0; i < jumps.size(); ++i) {
    const int j = s.moved_joints[i];
    (j == N ? *seam : joints[static_cast<std::size_t>(j - 1)]).jump = jumps[i];
  }
  return fold_pixel(s.spline, segs, joints, seam);
}

std::vector<std::array<double, 2>> SpaceRegionProblem::affine_bezier(int segment) const {
  const State& s = *state_;
  CMR_CHECK(!s.spline.is_rational());
  const SpaceWindow w = space_window(s.spline, s.spline.segments()[static_cast<std::size_t>(segment)]);
  const int k = s.request.point, twin = s.spline.twin(k);
  // F: the window with the moved point at 0; m: the blossom of the scalar
  // data that is 1 at the moved point (and its twin), 0 elsewhere.
  std::vector<Point3<Rational>> pts = space_window_points<Rational>(s.spline, w);
  std::vector<Rational> unit(static_cast<std::size_t>(w.degree + 1), Rational(0));
  for (int i = 0; i <= w.degree; ++i)
    if (w.first + i == k || w.first + i == twin) {
      pts[static_cast<std::size_t>(i)] = Point3<Rational>{Rational(0), Rational(0), Rational(0)};
      unit[static_cast<std::size_t>(i)] = 1;
    }
  const std::vector<Point3<Rational>> F = space_window_bezier<Rational>(w, pts);
  const std::vector<Rational> m = space_window_bezier_of<Rational>(w, unit);
  const auto rounded = rounded_with_bound;
  std::vector<std::array<double, 2>> out;
  for (int i = 0; i <= w.degree; ++i) {
    const auto ii = static_cast<std::size_t>(i);
    out.push_back(rounded(F[ii].x));
    out.push_back(rounded(F[ii].y));
    out.push_back(rounded(F[ii].z));
    out.push_back(rounded(m[ii]));
  }
  return out;
}

namespace {

/// The exact moved point Q at (a0 + x, b0 + y).
Point3<Rational> plane_point(const SpacePlane& pl, double a0, double b0, const Rational& x, const Rational& y) {
  const Rational a = Rational(a0) + x, b = Rational(b0) + y;
  const auto c = [&](double o, double u, double v) {
    return Rational(Rational(o) + a * Rational(u) + b * Rational(v));
  };
  return {c(pl.origin.x, pl.u.x, pl.v.x), c(pl.origin.y, pl.u.y, pl.v.y), c(pl.origin.z, pl.u.z, pl.v.z)};
}

}  // namespace

std::vector<SpaceRegionProblem::PlanePolynomial> SpaceRegionProblem::rational_lambda3(int segment, double a0,
                                                                                     double b0) const {
  const State& s = *state_;
  CMR_CHECK(s.spline.is_rational());
  const SpaceWindow w = space_window(s.spline, s.spline.segments()[static_cast<std::size_t>(segment)]);
  const int k = s.request.point, twin = s.spline.twin(k), n = s.spline.degree();
  return interpolate_plane(5, static_cast<std::size_t>(11 * n - 17), [&](const Rational& x, const Rational& y) {
    const Point3<Rational> q = plane_point(*s.request.plane, a0, b0, x, y);
    const auto H = moved_hwindow<Rational>(s.spline, w, k, twin, q);
    return lambda3_bernstein<Rational>(space_window_bezier<Rational>(w, H));
  });
}

std::array<SpaceRegionProblem::PlanePolynomial, 3> SpaceRegionProblem::rational_jump(int joint, double a0,
                                                                                   double b0) const {
  const State& s = *state_;
  CMR_CHECK(s.spline.is_rational());
  const int N = s.spline.segment_count(), k = s.request.point, twin = s.spline.twin(k);
  const SpaceWindow wl = space_window(s.spline, s.spline.segments()[static_cast<std::size_t>(joint - 1)]);
  const SpaceWindow wr = space_window(s.spline, s.spline.segments()[static_cast<std::size_t>(joint % N)]);
  const auto p = interpolate_plane(8, 3, [&](const Rational& x, const Rational& y) {
    const Point3<Rational> q = plane_point(*s.request.plane, a0, b0, x, y);
    const JumpTerms<Rational> t =
        jump_terms3<Rational>(space_window_bezier<Rational>(wl, moved_hwindow<Rational>(s.spline, wl, k, twin, q)),
                              space_window_bezier<Rational>(wr, moved_hwindow<Rational>(s.spline, wr, k, twin, q)));
    return std::vector<Rational>{t.gl, t.gr, t.d};
  });
  return {lowered(p[0], 2), lowered(p[1], 2), p[2]};
}

RegionResult SpaceRegionProblem::render(int threads) const {
  const auto start = std::chrono::steady_clock::now();
  const SpaceRegionRequest& r = state_->request;
  RegionResult out = RegionResult::blank(r.width, r.height, *r.view);
  const std::size_t n = out.size();
  std::vector<std::uint8_t> exact(n, 0);
  // The render's time budget (SpaceRegionRequest::time_limit): past it, or
  // projected past 4 times it after the first second, the render stops.
  std::atomic<std::size_t> done{0};
  std::atomic<bool> over{false};
  const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  parallel_for(static_cast<std::size_t>(r.height), threads, [&](std::size_t j) {
    for (int i = 0; i < r.width; ++i) {
      if (over.load(std::memory_order_relaxed)) return;
      const Vec2 c = pixel_center(out.view, r.width, r.height, i, static_cast<int>(j));
      const RegionPixel p = classify(c.x, c.y);
      const std::size_t idx = j * static_cast<std::size_t>(r.width) + static_cast<std::size_t>(i);
      out.labels[idx] = p.label;
      out.depth[idx] = p.depth;
      exact[idx] = p.exact ? 1 : 0;
      const std::size_t finished = ++done;
      if (r.time_limit > 0 && (p.exact || finished % 256 == 0)) {
        const double t = seconds();
        if (t > r.time_limit || (t > 1 && t * static_cast<double>(n) / static_cast<double>(finished) > 4 * r.time_limit))
          over = true;
      }
    }
  });
  if (over) {
    const double t = seconds(), per_pixel = t / static_cast<double>(std::max<std::size_t>(done, 1));
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "space region: %dx%d pixels would take about %.0f s (%.2g ms a pixel after %zu pixels: exact "
                  "arithmetic, e.g. for extreme weights); more than the limit of %g s per render",
                  r.width, r.height, per_pixel * static_cast<double>(n), per_pixel * 1e3, done.load(), r.time_limit);
    throw InputFieldError(std::string(buf) + " (a smaller " + field("size") + ")");
  }
  for (const std::uint8_t e : exact) out.exact_pixels += e;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace cmr
