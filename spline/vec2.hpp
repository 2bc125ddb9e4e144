#pragma once
// 2D point types. Public APIs use cmr::Vec2 (glm::dvec2). Generic algorithms
// (the blossom, the Bernstein algebra, lambda/eta) are templates over a scalar
// type so that the same code runs in double, in double with a running error
// bound (numeric/bounded.hpp) and in exact rational arithmetic (GMP); Vec2T
// is the point type they use for non-double scalars.
#include <type_traits>
#include <utility>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace cmr {

using Vec2 = glm::dvec2;

template <class T>
struct Vec2T {
  T x{}, y{};
  Vec2T() = default;
  Vec2T(T x_, T y_) : x(std::move(x_)), y(std::move(y_)) {}
  friend Vec2T operator+(const Vec2T& a, const Vec2T& b) { return {a.x + b.x, a.y + b.y}; }
  friend Vec2T operator-(const Vec2T& a, const Vec2T& b) { return {a.x - b.x, a.y - b.y}; }
  friend Vec2T operator*(const T& s, const Vec2T& a) { return {s * a.x, s * a.y}; }
};

/// The point type generic code uses for scalar T: glm's for double.
template <class T>
struct PointOf {
  using type = Vec2T<T>;
};
template <>
struct PointOf<double> {
  using type = Vec2;
};
template <class T>
using Point = typename PointOf<T>::type;

template <class T>
Point<T> to_point(const Vec2& p) {
  return Point<T>{T(p.x), T(p.y)};
}

/// A homogeneous point (w x, w y, w) of a rational curve (spline/bspline.hpp),
/// for non-double scalars; HPoint<double> is glm::dvec3. The blossom and every
/// Bernstein routine treat it like any other point type.
template <class T>
struct Vec3T {
  T x{}, y{}, z{};
  Vec3T() = default;
  Vec3T(T x_, T y_, T z_) : x(std::move(x_)), y(std::move(y_)), z(std::move(z_)) {}
  friend Vec3T operator+(const Vec3T& a, const Vec3T& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Vec3T operator-(const Vec3T& a, const Vec3T& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend Vec3T operator*(const T& s, const Vec3T& a) { return {s * a.x, s * a.y, s * a.z}; }
};

template <class T>
struct HPointOf {
  using type = Vec3T<T>;
};
template <>
struct HPointOf<double> {
  using type = glm::dvec3;
};
template <class T>
using HPoint = typename HPointOf<T>::type;

/// (w x, w y, w) from the Cartesian point p and its weight w, in scalar T
/// (exact for T = Rational; Bounded carries the two roundings).
template <class T>
HPoint<T> to_hpoint(const Vec2& p, double w) {
  const T tw(w);
  return HPoint<T>{T(p.x) * tw, T(p.y) * tw, tw};
}

/// det(a, b) = a.x*b.y - a.y*b.x, the signed area spanned by a and b.
// The explicit return type evaluates GMP expression templates before the
// temporaries they refer to go away.
template <class P>
auto det(const P& a, const P& b) -> std::remove_cvref_t<decltype(a.x)> {
  return a.x * b.y - a.y * b.x;
}
template <class P>
auto dot(const P& a, const P& b) -> std::remove_cvref_t<decltype(a.x)> {
  return a.x * b.x + a.y * b.y;
}

}  // namespace cmr
