#pragma once
// Seeded designer-like point sets for κ-curve tests (bezierize, report):
// 4-12 points at sorted random angles around a circle of radius 1 +- 30%
// (as a designer clicks around a shape), every other set closed.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "spline/vec2.hpp"

namespace cmr::test {

struct PointSet {
  std::vector<Vec2> points;
  bool closed = false;
  /// "closed [x,y][x,y]..." with every digit, to rerun a failing case.
  std::string str() const {
    std::ostringstream s;
    s.precision(17);
    s << (closed ? "closed " : "open ");
    for (const Vec2& p : points) s << '[' << p.x << ',' << p.y << ']';
    return s.str();
  }
};

inline std::vector<PointSet> designer_sets(unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> size(4, 12);
  std::uniform_real_distribution<double> angle(0, 2 * std::numbers::pi), radius(0.7, 1.3);
  std::vector<PointSet> out;
  for (int c = 0; c < count; ++c) {
    PointSet s;
    s.closed = c % 2 == 1;
    std::vector<double> a(size(rng));
    for (double& x : a) x = angle(rng);
    std::sort(a.begin(), a.end());
    for (double x : a) {
      const double r = radius(rng);
      s.points.push_back({r * std::cos(x), r * std::sin(x)});
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace cmr::test
