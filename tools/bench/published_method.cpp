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

/// kLanes doubles, one pixel per lane (GCC vector extensions; the compiler
/// maps them on the widest vector instructions the build's flags allow).
inline constexpr int kLanes = 4;
typedef double Lanes __attribute__((vector_size(kLanes * sizeof(double))));
typedef long long LaneMask __attribute__((vector_size(kLanes * sizeof(double))));

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
/// after unrolling: every bound and weight is a compile-time constant. T is
/// double (one pixel) or Lanes (kLanes pixels, the same operations in the same
/// order, so every lane rounds as the scalar code does).
template <int N, class T>
void lambda_fixed(const T* Px, const T* Py, T* xi) {
  constexpr int m = N - 1, dn = 2 * N - 4, dg = 2 * N - 2, dl = 4 * N - 7;
  constexpr auto cm = binomials<m>();
  constexpr auto cn1 = binomials<dn - 1>(), cg1 = binomials<dg - 1>();
  constexpr auto inv_n = inverse_binomials<dn>(), inv_g = inverse_binomials<dg>(), inv_l = inverse_binomials<dl>();
  T qx[m + 1], qy[m + 1];
#pragma GCC unroll 16
  for (int i = 0; i <= m; ++i) {
    qx[i] = double(N) * (Px[i + 1] - Px[i]);
    qy[i] = double(N) * (Py[i + 1] - Py[i]);
  }
  T nu_s[dn + 1], g_s[dg + 1];  // binomially scaled ν and g
  for (T& v : nu_s) v = T{} + 0.0;
  for (T& v : g_s) v = T{} + 0.0;
#pragma GCC unroll 16
  for (int i = 0; i <= m; ++i) {
    g_s[2 * i] += (cm[i] * cm[i]) * (qx[i] * qx[i] + qy[i] * qy[i]);
#pragma GCC unroll 16
    for (int j = i + 1; j <= m; ++j) {
      const double w = cm[i] * cm[j];
      nu_s[i + j - 1] += (double(j - i) * w) * (qx[i] * qy[j] - qy[i] * qx[j]);
      g_s[i + j] += (2 * w) * (qx[i] * qx[j] + qy[i] * qy[j]);
    }
  }
  T d_s[dn], e_s[dg];  // scaled η' (degree dn-1) and g' (degree dg-1)
#pragma GCC unroll 32
  for (int k = 0; k < dn; ++k) d_s[k] = (cn1[k] * dn) * (nu_s[k + 1] * inv_n[k + 1] - nu_s[k] * inv_n[k]);
#pragma GCC unroll 32
  for (int k = 0; k < dg; ++k) e_s[k] = (cg1[k] * dg) * (g_s[k + 1] * inv_g[k + 1] - g_s[k] * inv_g[k]);
  T a[dl + 1], b[dl + 1];  // scaled η' g and η g'
  for (T& v : a) v = T{} + 0.0;
  for (T& v : b) v = T{} + 0.0;
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

template <int N>
void lambda_fixed(const Vec2* P, double* xi) {
  double x[N + 1], y[N + 1];
  for (int i = 0; i <= N; ++i) {
    x[i] = P[i].x;
    y[i] = P[i].y;
  }
  lambda_fixed<N, double>(x, y, xi);
}

/// ξ_0 = λ(0) alone, from the first four points (the same formulas at k = 0:
/// ν_0 = m det(q_0,q_1), ν_1 = 2 C(m,2) det(q_0,q_2) / (2n-4), g_0 = q_0·q_0,
/// g_1 = 2 m q_0·q_1 / (2n-2), ξ_0 = (2n-4)(ν_1-ν_0) g_0 - (3/2) ν_0 (2n-2)(g_1-g_0)).
/// ξ_{4n-7} is the same of the reversed points (λ of the reversed curve is λ(1-t)).
/// Lets a pixel fail condition (3) at level 0 before its full ξ is formed.
template <int N, class T>
void lambda_start(const T& x0, const T& y0, const T& x1, const T& y1, const T& x2, const T& y2, const T& x3,
                  const T& y3, T& out) {
  constexpr int m = N - 1, dn = 2 * N - 4, dg = 2 * N - 2;
  const T q0x = double(N) * (x1 - x0), q0y = double(N) * (y1 - y0);
  const T q1x = double(N) * (x2 - x1), q1y = double(N) * (y2 - y1);
  const T q2x = double(N) * (x3 - x2), q2y = double(N) * (y3 - y2);
  const T nu0 = double(m) * (q0x * q1y - q0y * q1x);
  const T nu1 = (m * (m - 1) / double(dn)) * (q0x * q2y - q0y * q2x);
  const T g0 = q0x * q0x + q0y * q0y, g1 = (2.0 * m / dg) * (q0x * q1x + q0y * q1y);
  out = double(dn) * (nu1 - nu0) * g0 - (1.5 * dg) * nu0 * (g1 - g0);
}

template <int N>
double lambda_start(Vec2 p0, Vec2 p1, Vec2 p2, Vec2 p3) {
  double out;
  lambda_start<N, double>(p0.x, p0.y, p1.x, p1.y, p2.x, p2.y, p3.x, p3.y, out);
  return out;
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

/// Algorithm 1 (as algorithm1_fixed) for kLanes pixels at once: each lane has
/// its own depth-first traversal; every step examines every lane's current
/// piece and halves all of them with one vector de Casteljau, and lanes
/// that have finished are masked out. A lane's pending right halves sit in
/// `pending` at their level (depth first, left first: at most one per level),
/// marked in the lane's bit set. Returns each lane's verdict.
template <int K>
std::array<Verdict, kLanes> algorithm1_lanes(const Lanes* xi, int max_depth, unsigned active) {
  Lanes cur[K], left[K];
  Lanes pending[kMaxDepth + 2][K];
  std::copy(xi, xi + K, cur);
  int level[kLanes] = {};
  std::uint64_t waiting[kLanes] = {};  // bit L: a right half pending at level L
  bool inc[kLanes] = {}, dec[kLanes] = {}, undecided[kLanes] = {};
  std::array<Verdict, kLanes> out{};
  const auto finish = [&](int l, Verdict v) {
    out[l] = v;
    active &= ~(1u << l);
  };
  while (active) {
    Lanes lo = cur[0], hi = cur[0];
#pragma GCC unroll 32
    for (int i = 1; i < K; ++i) {
      lo = lo < cur[i] ? lo : cur[i];
      hi = hi > cur[i] ? hi : cur[i];
    }
    const LaneMask differ = ((cur[0] < 0) & (cur[K - 1] > 0)) | ((cur[0] > 0) & (cur[K - 1] < 0));
    const LaneMask ge = lo >= 0, le = hi <= 0;
    bool any_split = false;
    unsigned split = 0, popped = 0;
    for (int l = 0; l < kLanes; ++l) {
      if (!((active >> l) & 1)) continue;
      if (differ[l]) {
        finish(l, Verdict::none);
        continue;
      }
      if (ge[l] && le[l]) {
        finish(l, Verdict::constant);
        continue;
      }
      if (ge[l] || le[l]) {
        (ge[l] ? inc : dec)[l] = true;
      } else if (level[l] < max_depth) {
        split |= 1u << l;
        any_split = true;
        continue;
      } else {
        undecided[l] = true;
      }
      if (inc[l] && dec[l]) {
        finish(l, Verdict::none);
        continue;
      }
      if (waiting[l] == 0) {  // the lane's traversal is over
        finish(l, undecided[l] ? Verdict::undecided
                               : (inc[l] || !dec[l] ? Verdict::increasing : Verdict::decreasing));
        continue;
      }
      const int L = 63 - __builtin_clzll(waiting[l]);  // the most recent pending piece
      waiting[l] &= ~(std::uint64_t{1} << L);
      level[l] = L;
      popped |= 1u << l;
    }
    if (!any_split) {
      for (int l = 0; l < kLanes; ++l)
        if ((popped >> l) & 1)
#pragma GCC unroll 32
          for (int i = 0; i < K; ++i) cur[i][l] = pending[level[l]][i][l];
      continue;
    }
    // de Casteljau at 1/2 on every lane: left in `left`, cur becomes the right half.
    left[0] = cur[0];
#pragma GCC unroll 32
    for (int r = 1; r < K; ++r) {
#pragma GCC unroll 32
      for (int i = 0; i < K - r; ++i) cur[i] = 0.5 * (cur[i] + cur[i + 1]);
      left[r] = cur[0];
    }
    // Splitting lanes keep the right half pending and go on with the left;
    // popped lanes take their pending piece.
    for (int l = 0; l < kLanes; ++l) {
      if ((split >> l) & 1) {
        const int L = ++level[l];
        waiting[l] |= std::uint64_t{1} << L;
#pragma GCC unroll 32
        for (int i = 0; i < K; ++i) {
          pending[L][i][l] = cur[i][l];
          cur[i][l] = left[i][l];
        }
      } else if ((popped >> l) & 1) {
#pragma GCC unroll 32
        for (int i = 0; i < K; ++i) cur[i][l] = pending[level[l]][i][l];
      }
    }
  }
  return out;
}

/// Algorithm 1 with level 0 decided for kLanes pixels at once (rules (3), (1)
/// and (2) on vectors) and the lanes that must split continuing one by one
/// on algorithm1_fixed (the same pieces, the same arithmetic).
template <int K>
std::array<Verdict, kLanes> algorithm1_level0_lanes(const Lanes* xi, int max_depth, unsigned active) {
  Lanes lo = xi[0], hi = xi[0];
#pragma GCC unroll 32
  for (int i = 1; i < K; ++i) {
    lo = lo < xi[i] ? lo : xi[i];
    hi = hi > xi[i] ? hi : xi[i];
  }
  const LaneMask differ = ((xi[0] < 0) & (xi[K - 1] > 0)) | ((xi[0] > 0) & (xi[K - 1] < 0));
  const LaneMask ge = lo >= 0, le = hi <= 0;
  std::array<Verdict, kLanes> out{};
  for (int l = 0; l < kLanes; ++l) {
    if (!((active >> l) & 1)) continue;
    if (differ[l]) out[l] = Verdict::none;
    else if (ge[l] && le[l]) out[l] = Verdict::constant;
    else if (ge[l]) out[l] = Verdict::increasing;
    else if (le[l]) out[l] = Verdict::decreasing;
    else if (max_depth == 0) out[l] = Verdict::undecided;
    else {
      double c[K];
#pragma GCC unroll 32
      for (int i = 0; i < K; ++i) c[i] = xi[i][l];
      out[l] = algorithm1_fixed<K>(c, max_depth);
    }
  }
  return out;
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

  /// Labels of `count` <= kLanes pixels at (px, py), one per lane.
  void lanes(const Lanes& px, const Lanes& py, int count, bool lockstep, uint8_t* out) const {
    const Lanes dx = px - anchor_.x, dy = py - anchor_.y;
    unsigned active = (1u << count) - 1;
    const int segs = static_cast<int>(moved_.size());
    Lanes X[N + 1][N + 1], Y[N + 1][N + 1];
    for (int s = 0; s < segs; ++s) {  // the level-0 test (3) on ξ's ends first, as pixel() does
      const MovedSegment<N>& m = moved_[s];
#pragma GCC unroll 16
      for (int i = 0; i <= N; ++i) {
        X[s][i] = m.base[i].x + m.w[i] * dx;
        Y[s][i] = m.base[i].y + m.w[i] * dy;
      }
      const Lanes* x = X[s];
      const Lanes* y = Y[s];
      Lanes first, last;
      lambda_start<N, Lanes>(x[0], y[0], x[1], y[1], x[2], y[2], x[3], y[3], first);
      lambda_start<N, Lanes>(x[N], y[N], x[N - 1], y[N - 1], x[N - 2], y[N - 2], x[N - 3], y[N - 3], last);
      const LaneMask differ = ((first < 0) & (last > 0)) | ((first > 0) & (last < 0));
      for (int l = 0; l < kLanes; ++l)
        if (differ[l]) active &= ~(1u << l);
    }
    Directions dir[kLanes];
    for (Directions& d : dir) d = fixed_;
    if (active) {
      Lanes xi[N + 1][K];
      for (int s = 0; s < segs; ++s) lambda_fixed<N, Lanes>(X[s], Y[s], xi[s]);
      for (int s = 0; s < segs && active; ++s) {
        const std::array<Verdict, kLanes> v = lockstep ? algorithm1_lanes<K>(xi[s], r_.max_depth, active)
                                                         : algorithm1_level0_lanes<K>(xi[s], r_.max_depth, active);
        for (int l = 0; l < kLanes; ++l) {
          if (!((active >> l) & 1)) continue;
          dir[l].add(v[l]);
          if (dir[l].none || (dir[l].inc && dir[l].dec)) active &= ~(1u << l);
        }
      }
    }
    for (int l = 0; l < count; ++l) out[l] = (active >> l) & 1 ? dir[l].label() : 0;
  }

  PublishedHostPart host_part() const {
    PublishedHostPart h;
    h.degree = N;
    h.anchor = anchor_;
    h.segments = static_cast<int>(moved_.size());
    for (const MovedSegment<N>& m : moved_)
      for (int i = 0; i <= N; ++i) h.data.insert(h.data.end(), {m.base[i].x, m.base[i].y, m.w[i]});
    h.fixed_directions = (fixed_.inc ? 1u : 0u) | (fixed_.dec ? 2u : 0u) | (fixed_.undecided ? 4u : 0u);
    h.all_zero = fixed_.label() == 0;
    return h;
  }

  /// run() with kLanes pixels of a row at a time.
  std::vector<uint8_t> run_lanes(bool lockstep) const {
    std::vector<uint8_t> labels(static_cast<std::size_t>(r_.width) * r_.height, 0);
    if (fixed_.label() == 0) return labels;
    parallel_for(static_cast<std::size_t>(r_.height), r_.threads, [&](std::size_t j) {
      uint8_t* row = labels.data() + j * r_.width;
      for (int i = 0; i < r_.width; i += kLanes) {
        const int count = std::min(kLanes, r_.width - i);
        Lanes px, py;
        for (int l = 0; l < kLanes; ++l) {  // a short last group repeats its last pixel
          const Vec2 p = pixel_center(r_.view, r_.width, r_.height, i + std::min(l, count - 1), static_cast<int>(j));
          px[l] = p.x;
          py[l] = p.y;
        }
        lanes(px, py, count, lockstep, row + i);
      }
    });
    return labels;
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

std::vector<uint8_t> published_region_lanes(const BSpline& spline, const PublishedRegion& request, bool lockstep) {
  validate(spline, request);
  return by_degree(spline.degree(), [&]<int N>() { return Kernel<N>(spline, request).run_lanes(lockstep); });
}

PublishedHostPart published_host_part(const BSpline& spline, const PublishedRegion& request) {
  validate(spline, request);
  return by_degree(spline.degree(), [&]<int N>() { return Kernel<N>(spline, request).host_part(); });
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
