#include "region/pixel_simd.hpp"

#include <atomic>
#include <cmath>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace cmr::backend {

namespace {

constexpr int kTerms = 10;  // poly3.hpp's monomials: 1, dx, dy, x2, xy, y2, x2 dx, x2 dy, y2 dx, y2 dy

std::atomic<int> g_forced{-1};
std::atomic<bool> g_fault{false};
std::atomic<std::uint64_t> g_pixels[3];
thread_local std::uint64_t tl_pixels[3];

// v[c] = sum_m t[m * N + c] mu[m], in the order m = 0, 1, ..., 9 (the order
// eval_poly sums in; the bound does not depend on it).
template <int N>
void root_values(const double* t, const double* mu, double* v) {
  double acc[N] = {};
  for (int m = 0; m < kTerms; ++m)
    for (int c = 0; c < N; ++c) acc[c] += t[m * N + c] * mu[m];
  for (int c = 0; c < N; ++c) v[c] = acc[c];
}

// One pixel in plain C++ (the per-pixel code the render had before the SIMD levels).
void root_values_scalar(const double* t, const double* mag, int n1, double dx, double dy, double* v, int stride,
                        double* e, double units, double tiny) {
  const double x2 = dx * dx, xy = dx * dy, y2 = dy * dy;
  const double mu[kTerms] = {1, dx, dy, x2, xy, y2, x2 * dx, x2 * dy, y2 * dx, y2 * dy};
  double sum = 0;
  for (int m = 0; m < kTerms; ++m) sum += mag[m] * std::fabs(mu[m]);
  *e = units * sum + tiny;
  double out[30];
  switch (n1) {  // straight-line code for the common sizes (cubic: 6; quartic: 10; degree 9: 30)
    case 6: root_values<6>(t, mu, out); break;
    case 10: root_values<10>(t, mu, out); break;
    case 30: root_values<30>(t, mu, out); break;
    default:
      for (int c = 0; c < n1; ++c) v[static_cast<std::size_t>(c) * stride] = 0;
      for (int m = 0; m < kTerms; ++m)
        for (int c = 0; c < n1; ++c) v[static_cast<std::size_t>(c) * stride] += t[m * n1 + c] * mu[m];
      return;
  }
  for (int c = 0; c < n1; ++c) v[static_cast<std::size_t>(c) * stride] = out[c];
}

#if defined(__x86_64__)

// Two pixels per instruction; SSE2 is the x86-64 baseline. _mm_mul_pd and
// _mm_add_pd are the scalar code's roundings, lane by lane.
void root_values_sse2(const double* t, const double* mag, int n1, const double* dx, const double* dy, double* v,
                      int stride, double* e, double units, double tiny) {
  const __m128d x = _mm_loadu_pd(dx), y = _mm_loadu_pd(dy);
  const __m128d x2 = _mm_mul_pd(x, x), xy = _mm_mul_pd(x, y), y2 = _mm_mul_pd(y, y);
  const __m128d mu[kTerms] = {_mm_set1_pd(1.0),  x,  y,  x2, xy, y2, _mm_mul_pd(x2, x), _mm_mul_pd(x2, y),
                              _mm_mul_pd(y2, x), _mm_mul_pd(y2, y)};
  const __m128d sign = _mm_set1_pd(-0.0);
  __m128d sum = _mm_setzero_pd();
  for (int m = 0; m < kTerms; ++m) sum = _mm_add_pd(sum, _mm_mul_pd(_mm_set1_pd(mag[m]), _mm_andnot_pd(sign, mu[m])));
  _mm_storeu_pd(e, _mm_add_pd(_mm_mul_pd(_mm_set1_pd(units), sum), _mm_set1_pd(tiny)));
  for (int c = 0; c < n1; ++c) {
    __m128d acc = _mm_setzero_pd();
    for (int m = 0; m < kTerms; ++m) acc = _mm_add_pd(acc, _mm_mul_pd(_mm_set1_pd(t[m * n1 + c]), mu[m]));
    _mm_storeu_pd(v + static_cast<std::size_t>(c) * stride, acc);
  }
}

// Four pixels per instruction. target("avx2") only: no FMA, so the compiler
// cannot contract a multiply and an add into one rounding.
__attribute__((target("avx2"))) void root_values_avx2(const double* t, const double* mag, int n1, const double* dx,
                                                      const double* dy, double* v, int stride, double* e,
                                                      double units, double tiny) {
  const __m256d x = _mm256_loadu_pd(dx), y = _mm256_loadu_pd(dy);
  const __m256d x2 = _mm256_mul_pd(x, x), xy = _mm256_mul_pd(x, y), y2 = _mm256_mul_pd(y, y);
  const __m256d mu[kTerms] = {_mm256_set1_pd(1.0),  x,  y,  x2, xy, y2, _mm256_mul_pd(x2, x), _mm256_mul_pd(x2, y),
                              _mm256_mul_pd(y2, x), _mm256_mul_pd(y2, y)};
  const __m256d sign = _mm256_set1_pd(-0.0);
  __m256d sum = _mm256_setzero_pd();
  for (int m = 0; m < kTerms; ++m)
    sum = _mm256_add_pd(sum, _mm256_mul_pd(_mm256_set1_pd(mag[m]), _mm256_andnot_pd(sign, mu[m])));
  _mm256_storeu_pd(e, _mm256_add_pd(_mm256_mul_pd(_mm256_set1_pd(units), sum), _mm256_set1_pd(tiny)));
  for (int c = 0; c < n1; ++c) {
    __m256d acc = _mm256_setzero_pd();
    for (int m = 0; m < kTerms; ++m) acc = _mm256_add_pd(acc, _mm256_mul_pd(_mm256_set1_pd(t[m * n1 + c]), mu[m]));
    _mm256_storeu_pd(v + static_cast<std::size_t>(c) * stride, acc);
  }
}

bool cpu_has_avx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

#endif

}  // namespace

const char* simd_name(SimdLevel level) {
  switch (level) {
    case SimdLevel::scalar: return "scalar";
    case SimdLevel::sse2: return "sse2";
    case SimdLevel::avx2: return "avx2";
  }
  return "scalar";
}

int simd_lanes(SimdLevel level) { return level == SimdLevel::avx2 ? 4 : level == SimdLevel::sse2 ? 2 : 1; }

bool simd_available(SimdLevel level) {
#if defined(__x86_64__)
  static const bool avx2 = cpu_has_avx2();
  return level != SimdLevel::avx2 || avx2;
#else
  return level == SimdLevel::scalar;
#endif
}

SimdLevel best_simd_level() {
  return simd_available(SimdLevel::avx2) ? SimdLevel::avx2
         : simd_available(SimdLevel::sse2) ? SimdLevel::sse2
                                           : SimdLevel::scalar;
}

std::optional<SimdLevel> parse_simd_level(std::string_view text) {
  for (const SimdLevel l : {SimdLevel::scalar, SimdLevel::sse2, SimdLevel::avx2})
    if (text == simd_name(l)) return l;
  return std::nullopt;
}

SimdLevel simd_level_for(const char* env, std::string& warning) {
  warning.clear();
  const SimdLevel best = best_simd_level();
  if (!env || !*env) return best;
  const std::optional<SimdLevel> want = parse_simd_level(env);
  if (!want) {
    warning = std::string("cmr: CMR_SIMD=") + env + " is not scalar, sse2 or avx2; using " + simd_name(best);
    return best;
  }
  if (!simd_available(*want)) {
    warning = std::string("cmr: CMR_SIMD=") + env + ": this CPU or build lacks it; using " + simd_name(best);
    return best;
  }
  return *want;
}

SimdLevel simd_level() {
  const int forced = g_forced.load(std::memory_order_relaxed);
  if (forced >= 0) return static_cast<SimdLevel>(forced);
  return best_simd_level();
}

bool set_simd_level(SimdLevel level) {
  if (!simd_available(level)) return false;
  g_forced.store(static_cast<int>(level), std::memory_order_relaxed);
  return true;
}

void pixel_root_values(SimdLevel level, const double* t, const double* mag, int n1, const double* dx,
                       const double* dy, double* v, int stride, double* e, double units, double tiny) {
  switch (level) {
#if defined(__x86_64__)
    case SimdLevel::avx2: root_values_avx2(t, mag, n1, dx, dy, v, stride, e, units, tiny); break;
    case SimdLevel::sse2: root_values_sse2(t, mag, n1, dx, dy, v, stride, e, units, tiny); break;
#else
    case SimdLevel::avx2:
    case SimdLevel::sse2:
#endif
    case SimdLevel::scalar: root_values_scalar(t, mag, n1, dx[0], dy[0], v, stride, e, units, tiny); return;
  }
  if (g_fault.load(std::memory_order_relaxed)) v[1] = -v[1];  // test hook: lane 1's v[0] negated
}

std::uint64_t simd_pixel_count(SimdLevel level) {
  return g_pixels[static_cast<int>(level)].load(std::memory_order_relaxed);
}

void count_simd_pixels(SimdLevel level, int pixels) { tl_pixels[static_cast<int>(level)] += static_cast<std::uint64_t>(pixels); }

void publish_simd_pixel_counts() {
  for (int l = 0; l < 3; ++l) {
    if (tl_pixels[l] == 0) continue;
    g_pixels[l].fetch_add(tl_pixels[l], std::memory_order_relaxed);
    tl_pixels[l] = 0;
  }
}

void set_simd_fault_for_test(bool on) { g_fault.store(on, std::memory_order_relaxed); }

}  // namespace cmr::backend
