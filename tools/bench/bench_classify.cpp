// Classifier benchmark (issue: spline core). Prints
//  1. throughput of classify_bezier on random cubic spans, one core, in
//     memory, and how often the exact (rational) fallback ran;
//  2. correctness on hard curves: lambda with two roots within 1e-6 of each
//     other, or a root within 1e-9 of an end, at scales 2^-7 .. 2^7, against
//     the truth from certified root isolation (numeric/roots.hpp); and the
//     same curves judged by a sampled curvature-extremum search with an
//     absolute tolerance, as CAD kernels do it.
// Usage: bench_classify [spans=1000000]   (best of 5 passes)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "bezierize/classify.hpp"
#include "bezierize/lambda.hpp"
#include "numeric/roots.hpp"
#include "spline/curvature.hpp"

using namespace cmr;

namespace {

using Cubic = std::array<Vec2, 4>;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Bernstein<Rational> exact_lambda(const Cubic& c) {
  std::vector<Point<Rational>> P;
  for (const Vec2& p : c) P.push_back(to_point<Rational>(p));
  return lambda_bernstein<Rational>(P);
}

// Interior roots of lambda where it changes sign (the truth about monotonicity).
std::vector<RootInterval> interior_sign_changes(const Cubic& c) {
  std::vector<RootInterval> out;
  RootOptions o;
  o.tolerance = 1e-15;
  for (const RootInterval& r : isolate_roots(exact_lambda(c), o)) {
    const bool at_end = r.exact() && (sgn(r.lo) == 0 || r.lo == 1);
    if (r.sign_change() && !at_end) out.push_back(r);
  }
  return out;
}

Cubic random_cubic(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  return {Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng))};
}

// de Casteljau: the piece of c on [a, 1] (from_start = false) or [0, a].
Cubic piece(const Cubic& c, double a, bool keep_right) {
  Vec2 w[4] = {c[0], c[1], c[2], c[3]};
  Cubic left, right;
  left[0] = w[0];
  right[3] = w[3];
  for (int r = 1; r < 4; ++r) {
    for (int i = 0; i + r < 4; ++i) w[i] = (1 - a) * w[i] + a * w[i + 1];
    left[r] = w[0];
    right[3 - r] = w[3 - r];
  }
  return keep_right ? right : left;
}

double mid(const RootInterval& r) { return 0.5 * (r.lo.get_d() + r.hi.get_d()); }

// A cubic whose lambda has two interior roots about `gap` apart, found by
// moving P3 along a direction until two sign changes merge (bisection on the
// exact root count). nullopt when this random start has no such merge.
std::optional<Cubic> close_roots(std::mt19937_64& rng, double gap) {
  const Cubic base = random_cubic(rng);
  std::uniform_real_distribution<double> u(-1, 1);
  const Vec2 dir(u(rng), u(rng));
  auto at = [&](double s) {
    Cubic c = base;
    c[3] += s * dir;
    return c;
  };
  double two = NAN, none = NAN, prev = -2;
  std::size_t prev_count = interior_sign_changes(at(prev)).size();
  for (double s = -1.9; s <= 2; s += 0.1) {
    const std::size_t n = interior_sign_changes(at(s)).size();
    if (prev_count == 2 && n == 0) { two = prev; none = s; break; }
    if (prev_count == 0 && n == 2) { two = s; none = prev; break; }
    prev = s;
    prev_count = n;
  }
  if (std::isnan(two)) return std::nullopt;
  for (int it = 0; it < 80; ++it) {
    const double m = 0.5 * (two + none);
    const auto roots = interior_sign_changes(at(m));
    if (roots.size() == 2) {
      two = m;
      if (mid(roots[1]) - mid(roots[0]) < gap) return at(m);
    } else if (roots.empty()) {
      none = m;
    } else {
      return std::nullopt;  // another root entered: give up on this start
    }
  }
  return std::nullopt;
}

// A cubic with one interior simple root, then cut so that the root lies
// `offset` inside (inside = true) or outside the new start.
std::optional<Cubic> root_near_end(std::mt19937_64& rng, double offset, bool inside) {
  const Cubic c = random_cubic(rng);
  const auto roots = interior_sign_changes(c);
  if (roots.size() != 1) return std::nullopt;
  const double r = mid(roots[0]);
  const double a = inside ? r - offset * (1 - r) : r + offset * (1 - r);
  if (a <= 0 || a >= 1) return std::nullopt;
  return piece(c, a, true);
}

// Sampled curvature-extremum search with an absolute tolerance: the curvature
// is called monotone when its sampled differences do not change sign by more
// than `tolerance`.
bool sampled_monotone(const Cubic& c, int samples, double tolerance) {
  const BSpline s = BSpline::bezier(std::vector<Vec2>(c.begin(), c.end()));
  bool up = false, down = false;
  double prev = curvature(s, 0.0);
  for (int i = 1; i < samples; ++i) {
    const double k = curvature(s, static_cast<double>(i) / (samples - 1));
    if (k - prev > tolerance) up = true;
    if (prev - k > tolerance) down = true;
    prev = k;
  }
  return !(up && down);
}

}  // namespace

int main(int argc, char** argv) {
  const int spans = argc > 1 ? std::atoi(argv[1]) : 1000000;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec2> pts(4 * static_cast<std::size_t>(spans));
  for (Vec2& p : pts) p = Vec2(u(rng), u(rng));

  std::printf("cmr classifier benchmark (one core, spans in memory, D = 12)\n\n");
  for (bool inflection : {false, true}) {
    ClassifyOptions o;
    o.inflection = inflection;
    long exact = 0, decided = 0;
    double sec = 1e300;  // best of 5 passes: the machine's speed varies between runs
    for (int pass = 0; pass < 5; ++pass) {
      const auto t0 = std::chrono::steady_clock::now();
      exact = decided = 0;
      for (int i = 0; i < spans; ++i) {
        const SegmentClass c = classify_bezier(std::span<const Vec2>(&pts[4 * static_cast<std::size_t>(i)], 4), o);
        exact += c.exact_used;
        decided += c.monotonicity.curvature != Curvature::undecided;
      }
      sec = std::min(sec, seconds_since(t0));
    }
    std::printf("random cubic spans, %-28s %8.2f M spans/s  (%d spans, %ld exact fallbacks, %ld decided)\n",
                inflection ? "Algorithms 1 and 2:" : "Algorithm 1 (monotonicity):", spans / sec / 1e6, spans,
                exact, decided);
  }

  // Hard curves.
  std::vector<std::pair<const char*, Cubic>> hard;
  std::mt19937_64 hrng(7);
  int want_close = 40, want_end = 40;
  while (want_close > 0) {
    if (auto c = close_roots(hrng, 1e-6)) {
      hard.push_back({"two roots < 1e-6 apart", *c});
      --want_close;
    }
  }
  while (want_end > 0) {
    const bool inside = want_end % 2 == 0;
    if (auto c = root_near_end(hrng, 1e-9, inside)) {
      hard.push_back({inside ? "root 1e-9 inside the start" : "root 1e-9 outside the start", *c});
      --want_end;
    }
  }
  int cases = 0, wrong = 0, undecided = 0, sampled_wrong = 0, sampled_cases = 0;
  long exact = 0;
  for (const auto& [kind, base] : hard) {
    for (int k = -7; k <= 7; ++k) {
      Cubic c = base;
      for (Vec2& p : c) p *= std::ldexp(1.0, k);  // exact scaling: the roots stay
      const bool truth_monotone = interior_sign_changes(c).empty();
      const SegmentClass got = classify_bezier(std::span<const Vec2>(c.data(), 4), {12, false});
      exact += got.exact_used;
      ++cases;
      switch (got.monotonicity.curvature) {
        case Curvature::undecided: ++undecided; break;
        case Curvature::non_monotone: wrong += truth_monotone; break;
        default: wrong += !truth_monotone; break;
      }
      if (k == 0) {
        ++sampled_cases;
        sampled_wrong += sampled_monotone(c, 1000, 1e-9) != truth_monotone;
      }
    }
  }
  std::printf("\nhard curves: %zu cubics x 15 scales (2^-7..2^7) = %d cases\n", hard.size(), cases);
  std::printf("  classify_bezier (D = 12):       %d wrong, %d undecided, %ld exact fallbacks\n", wrong, undecided,
              exact);
  std::printf("  sampled search (1000 samples, |dk| > 1e-9): %d wrong of %d (scale 1)\n", sampled_wrong,
              sampled_cases);
  return wrong == 0 ? 0 : 1;
}
