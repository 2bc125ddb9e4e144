#pragma once
// 2D point types. Public APIs use cmr::Vec2 (glm::dvec2). Generic algorithms
// (the blossom, the Bernstein algebra, lambda/eta) are templates over a scalar
// type so that the same code runs in double, in double with a running error
// bound (bezierize/bounded.hpp) and in exact rational arithmetic (GMP); Vec2T
// is the point type they use for non-double scalars.
#include <type_traits>
#include <utility>

#include <glm/vec2.hpp>

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
