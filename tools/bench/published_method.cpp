#include "tools/bench/published_method.hpp"

#include <algorithm>
#include <array>
#include <string>

#include "bezierize/extract.hpp"
#include "spline/errors.hpp"
#include "spline/limits.hpp"
#include "spline/parallel.hpp"

namespace cmr::bench {
namespace {

/// Row n of Pascal's triangle as doubles (exact up to n = 4 kPublishedMaxDegree).
template <int n>
constexpr std::array<double, n + 1> binomials() {
  std::array<double, n + 1> row{};
  row[0] = 1;
  for (int k = 1; k <= n; ++k) row[k] = row[k - 1] * (n - k + 1) / k;
  return row;
}

template <int n>
constexpr std::array<double, n + 1> inverse_binomials() {
  std::array<double, n + 1> row = binomials<n>();
  for (double& v : row) v = 1 / v;
  return row;
}

/// ξ of one Bézier segment of degree N (header: the formulas), straight-line
/// after unrolling: every bound and weight is a compile-time constant.
template <int N>
void lambda_fixed(const Vec2* P, double* xi) {
  constexpr int m = N - 1, dn = 2 * N - 4, dg = 2 * N - 2, dl = 4 * N - 7;
  constexpr auto cm = binomials<m>();
  constexpr auto cn1 = binomials<dn - 1>(), cg1 = binomials<dg - 1>();
  constexpr auto inv_n = inverse_binomials<dn>(), inv_g = inverse_binomials<dg>(), inv_l = inverse_binomials<dl>();
  double qx[m + 1], qy[m + 1];
#pragma GCC unroll 16
  for (int i = 0; i <= m; ++i) {
    qx[i] = N * (P[i + 1].x - P[i].x);
    qy[i] = N * (P[i + 1].y - P[i].y);
  }
  double nu_s[dn + 1] = {}, g_s[dg + 1] = {};  // binomially scaled ν and g
#pragma GCC unroll 16
  for (int i = 0; i <= m; ++i) {
    g_s[2 * i] += cm[i] * cm[i] * (qx[i] * qx[i] + qy[i] * qy[i]);
#pragma GCC unroll 16
    for (int j = i + 1; j <= m; ++j) {
      const double w = cm[i] * cm[j];
      nu_s[i + j - 1] += (j - i) * w * (qx[i] * qy[j] - qy[i] * qx[j]);
      g_s[i + j] += 2 * w * (qx[i] * qx[j] + qy[i] * qy[j]);
    }
  }
  double d_s[dn], e_s[dg];  // scaled η' (degree dn-1) and g' (degree dg-1)
#pragma GCC unroll 32
  for (int k = 0; k < dn; ++k) d_s[k] = cn1[k] * dn * (nu_s[k + 1] * inv_n[k + 1] - nu_s[k] * inv_n[k]);
#pragma GCC unroll 32
  for (int k = 0; k < dg; ++k) e_s[k] = cg1[k] * dg * (g_s[k + 1] * inv_g[k + 1] - g_s[k] * inv_g[k]);
  double a[dl + 1] = {}, b[dl + 1] = {};  // scaled η' g and η g'
#pragma GCC unroll 32
  for (int i = 0; i < dn; ++i)
#pragma GCC unroll 32
    for (int j = 0; j <= dg; ++j) a[i + j] += d_s[i] * g_s[j];
#pragma GCC unroll 32
  for (int i = 0; i <= dn; ++i)
#pragma GCC unroll 32
    for (int j = 0; j < dg; ++j) b[i + j] += nu_s[i] * e_s[j];
#pragma GCC unroll 32
  for (int k = 0; k <= dl; ++k) xi[k] = (a[k] - 1.5 * b[k]) * inv_l[k];
}

/// ξ_0 = λ(0) alone, from the first four points (the same formulas at k = 0:
/// ν_0 = m det(q_0,q_1), ν_1 = 2 C(m,2) det(q_0,q_2) / (2n-4), g_0 = q_0·q_0,
/// g_1 = 2 m q_0·q_1 / (2n-2), ξ_0 = (2n-4)(ν_1-ν_0) g_0 - (3/2) ν_0 (2n-2)(g_1-g_0)).
/// ξ_{4n-7} is the same of the reversed points (λ of the reversed curve is λ(1-t)).
/// Lets a pixel fail condition (3) at level 0 before its full ξ is formed.
template <int N>
double lambda_start(Vec2 p0, Vec2 p1, Vec2 p2, Vec2 p3) {
  constexpr int m = N - 1, dn = 2 * N - 4, dg = 2 * N - 2;
  const Vec2 q0 = double(N) * (p1 - p0), q1 = double(N) * (p2 - p1), q2 = double(N) * (p3 - p2);
  const double nu0 = m * (q0.x * q1.y - q0.y * q1.x);
  const double nu1 = (m * (m - 1) / double(dn)) * (q0.x * q2.y - q0.y * q2.x);
  const double g0 = q0.x * q0.x + q0.y * q0.y, g1 = (2.0 * m / dg) * (q0.x * q1.x + q0.y * q1.y);
  return dn * (nu1 - nu0) * g0 - 1.5 * nu0 * dg * (g1 - g0);
}

/// Condition (3) at level 0: ends of opposite sign.
inline bool ends_differ(double first, double last) { return (first < 0 && last > 0) || (first > 0 && last < 0); }

/// What Algorithm 1 says about one segment.
enum class Verdict : uint8_t { increasing, decreasing, none, undecided, constant };

/// Algorithm 1 (CAD&A 2024 §3) on K coefficients in plain double, depth first
/// with a fixed-size stack: (3) ends of opposite sign -> not monotone;
/// (1)/(2) all >= 0 / all <= 0 -> increasing / decreasing (both: λ ≡ 0);
/// else halve, left half visited first; a piece still mixed at level D is
/// undecided unless a later piece proves non-monotonicity. Same fold as
/// cmr's MonotonicityFold, without its error bounds.
template <int K>
Verdict algorithm1_fixed(const double* xi, int max_depth) {
  double stack[(kMaxDepth + 2) * K];
  int levels[kMaxDepth + 2];
  std::copy(xi, xi + K, stack);
  levels[0] = 0;
  int sp = 1;
  bool inc = false, dec = false, undecided = false;
  while (sp > 0) {
    --sp;
    double* c = stack + sp * K;
    const int level = levels[sp];
    if (ends_differ(c[0], c[K - 1])) return Verdict::none;
    double lo = c[0], hi = c[0];
#pragma GCC unroll 32
    for (int i = 1; i < K; ++i) {
      lo = std::min(lo, c[i]);
      hi = std::max(hi, c[i]);
    }
    if (lo >= 0 && hi <= 0) return Verdict::constant;
    if (lo >= 0) {
      inc = true;
    } else if (hi <= 0) {
      dec = true;
    } else if (level < max_depth) {
      // de Casteljau at 1/2: the left half goes to the slot above, c becomes the right half.
      double* left = c + K;
      left[0] = c[0];
#pragma GCC unroll 32
      for (int r = 1; r < K; ++r) {
#pragma GCC unroll 32
        for (int i = 0; i < K - r; ++i) c[i] = 0.5 * (c[i] + c[i + 1]);
        left[r] = c[0];
      }
      levels[sp] = levels[sp + 1] = level + 1;
      sp += 2;
      continue;
    } else {
      undecided = true;
    }
    if (inc && dec) return Verdict::none;
  }
  if (undecided) return Verdict::undecided;
  return inc || !dec ? Verdict::increasing : Verdict::decreasing;
}

/// Directions seen so far over a spline's segments (analyze.hpp's CMRWI rule
/// for C² splines: constant segments go with either direction).
struct Directions {
  bool inc = false, dec = false, undecided = false, none = false;
  void add(Verdict v) {
    inc = inc || v == Verdict::increasing;
    dec = dec || v == Verdict::decreasing;
    undecided = undecided || v == Verdict::undecided;
    none = none || v == Verdict::none;
  }
  uint8_t label() const {
    if (none || (inc && dec)) return 0;
    if (undecided) return 3;
    return dec ? 2 : 1;
  }
};

/// The touched segments of one image: B = base + w (p - P_k).
template <int N>
struct MovedSegment {
  std::array<Vec2, N + 1> base;
  std::array<double, N + 1> w;
};

template <int N>
class Kernel {
 public:
  static constexpr int K = 4 * N - 6;

  Kernel(const BSpline& spline, const PublishedRegion& r) : r_(r), anchor_(spline.points()[r.point]) {
    const std::vector<BezierSegment> segments = bezier_segments(spline);
    std::vector<bool> touched(segments.size(), false);
    for (const SegmentInfluence& si : influence(spline, {r.point})) {
      MovedSegment<N> s;
      for (int i = 0; i <= N; ++i) {
        s.base[i] = segments[si.segment].points[i];
        s.w[i] = si.w[i];
      }
      moved_.push_back(s);
      touched[si.segment] = true;
    }
    CMR_CHECK(static_cast<int>(moved_.size()) <= N + 1);
    for (std::size_t s = 0; s < segments.size(); ++s) {  // untouched: once per image
      if (touched[s]) continue;
      double xi[K];
      lambda_fixed<N>(segments[s].points.data(), xi);
      fixed_.add(algorithm1_fixed<K>(xi, r.max_depth));
    }
  }

  uint8_t pixel(Vec2 p) const {
    const Vec2 d = p - anchor_;
    double xi[N + 1][K];
    const int count = static_cast<int>(moved_.size());
    Vec2 P[N + 1][N + 1];
    for (int s = 0; s < count; ++s) {  // the level-0 test (3) on ξ's ends first: the cheap rejection
      const MovedSegment<N>& m = moved_[s];
#pragma GCC unroll 16
      for (int i = 0; i <= N; ++i) P[s][i] = m.base[i] + m.w[i] * d;
      const Vec2* b = P[s];
      if (ends_differ(lambda_start<N>(b[0], b[1], b[2], b[3]), lambda_start<N>(b[N], b[N - 1], b[N - 2], b[N - 3])))
        return 0;
    }
    for (int s = 0; s < count; ++s) lambda_fixed<N>(P[s], xi[s]);
    Directions dir = fixed_;
    for (int s = 0; s < count; ++s) {
      dir.add(algorithm1_fixed<K>(xi[s], r_.max_depth));
      if (dir.none || (dir.inc && dir.dec)) return 0;
    }
    return dir.label();
  }

  std::vector<uint8_t> run() const {
    std::vector<uint8_t> labels(static_cast<std::size_t>(r_.width) * r_.height, 0);
    if (fixed_.label() == 0) return labels;  // an untouched segment already fails
    parallel_for(static_cast<std::size_t>(r_.height), r_.threads, [&](std::size_t j) {
      uint8_t* row = labels.data() + j * r_.width;
      for (int i = 0; i < r_.width; ++i)
        row[i] = pixel(pixel_center(r_.view, r_.width, r_.height, i, static_cast<int>(j)));
    });
    return labels;
  }

 private:
  PublishedRegion r_;
  Vec2 anchor_;
  std::vector<MovedSegment<N>> moved_;
  Directions fixed_;
};

void check_degree(int n) {
  if (n < kPublishedMinDegree || n > kPublishedMaxDegree)
    throw InputError("the published-method baseline has code for degrees " + std::to_string(kPublishedMinDegree) +
                     ".." + std::to_string(kPublishedMaxDegree) + ", not " + std::to_string(n));
}

void validate(const BSpline& spline, const PublishedRegion& r) {
  check_degree(spline.degree());
  if (r.point < 0 || r.point >= spline.point_count())
    throw InputError("point " + std::to_string(r.point) + " is outside 0.." + std::to_string(spline.point_count() - 1));
  if (r.width < 1 || r.height < 1 || r.width > kMaxImageSize || r.height > kMaxImageSize)
    throw InputError("image size " + std::to_string(r.width) + "x" + std::to_string(r.height) + " is outside 1.." +
                     std::to_string(kMaxImageSize));
  if (r.max_depth < 0 || r.max_depth > kMaxDepth)
    throw InputError("depth " + std::to_string(r.max_depth) + " is outside 0.." + std::to_string(kMaxDepth));
  for (const Segment& s : spline.segments())
    if (s.index > 0 && spline.multiplicity(s.a) >= spline.degree() - 1)
      throw InputError("the published-method baseline needs a C2 spline; the knot " + std::to_string(s.a) +
                       " has multiplicity " + std::to_string(spline.multiplicity(s.a)));
}

/// Calls f.template operator()<N>() for the runtime degree n.
template <class F>
auto by_degree(int n, F&& f) {
  check_degree(n);
  switch (n) {
    case 3: return f.template operator()<3>();
    case 4: return f.template operator()<4>();
    case 5: return f.template operator()<5>();
    case 6: return f.template operator()<6>();
    case 7: return f.template operator()<7>();
    case 8: return f.template operator()<8>();
    default: return f.template operator()<9>();
  }
}
static_assert(kPublishedMinDegree == 3 && kPublishedMaxDegree == 9, "by_degree lists every degree");

}  // namespace

std::vector<uint8_t> published_region(const BSpline& spline, const PublishedRegion& request) {
  validate(spline, request);
  return by_degree(spline.degree(), [&]<int N>() { return Kernel<N>(spline, request).run(); });
}

std::vector<double> published_lambda(const std::vector<Vec2>& P) {
  return by_degree(static_cast<int>(P.size()) - 1, [&]<int N>() {
    std::vector<double> xi(4 * N - 6);
    lambda_fixed<N>(P.data(), xi.data());
    return xi;
  });
}

std::array<double, 2> published_lambda_ends(const std::vector<Vec2>& P) {
  return by_degree(static_cast<int>(P.size()) - 1, [&]<int N>() {
    return std::array<double, 2>{lambda_start<N>(P[0], P[1], P[2], P[3]),
                                 lambda_start<N>(P[N], P[N - 1], P[N - 2], P[N - 3])};
  });
}

}  // namespace cmr::bench
