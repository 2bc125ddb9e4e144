// eval_polys (box_eval.hpp): several piece polynomials over one box at once,
// one polynomial per lane, each lane doing eval_poly's IEEE operations in
// eval_poly's order (separate multiplies and adds: the AVX2 code is compiled
// with target("avx2") only, so nothing is contracted into a fused
// multiply-add), so every lane's value and bound are eval_poly's bit for bit
// (tests/region/box_eval_test.cpp, BoxEval.ManyAtOnceIsEvalPolyBitForBit).
#include <cmath>

#include "region/box_eval.hpp"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace cmr::backend::box_eval {

namespace {

constexpr int kTerms = kPoly3Terms;
constexpr double kUnits = kPolyErrorUnits * 0.5 * Bounded::kRound;
// eval_poly's factor of the regrouped rounding part, and its absolute slack.
constexpr double kMagFactor = kUnits * (1 + 32 * Bounded::kRound);
constexpr double kSlack = 16 * Bounded::kTiny;

#if defined(__x86_64__)

// Two polynomials a and b per instruction (SSE2, the x86-64 baseline).
void eval_two(const std::array<double, kTerms>& a, const std::array<double, kTerms>& b, const Monomials& m,
              Bounded* out) {
  __m128d c[kTerms];
  __m128d nonzero = _mm_setzero_pd();
  for (int i = 0; i < kTerms; ++i) {
    c[i] = _mm_set_pd(b[i], a[i]);
    nonzero = _mm_or_pd(nonzero, _mm_cmpneq_pd(c[i], _mm_setzero_pd()));
  }
  __m128d d[kTerms];
  for (int st = 0; st < kTerms; ++st) d[st] = _mm_setzero_pd();
#pragma GCC unroll 35
  for (int k = 0; k < Monomials::kPairs; ++k)
    d[kPairTable.st[k]] = _mm_add_pd(d[kPairTable.st[k]], _mm_mul_pd(c[kPairTable.m[k]], _mm_set1_pd(m.tv[k])));
  const __m128d sign = _mm_set1_pd(-0.0);
  __m128d mag = _mm_setzero_pd();
  for (int i = 0; i < kTerms; ++i) mag = _mm_add_pd(mag, _mm_mul_pd(_mm_andnot_pd(sign, c[i]), _mm_set1_pd(m.g[i])));
  __m128d err = _mm_add_pd(_mm_mul_pd(_mm_set1_pd(kMagFactor), mag), _mm_set1_pd(kSlack));
  for (int st = 1; st < kTerms; ++st)
    err = _mm_add_pd(err, _mm_mul_pd(_mm_andnot_pd(sign, d[st]), _mm_set1_pd(m.rw[st])));
  // An all-zero polynomial is exactly zero (eval_poly's first test).
  alignas(16) double v[2], e[2];
  _mm_store_pd(v, _mm_and_pd(d[0], nonzero));
  _mm_store_pd(e, _mm_and_pd(err, nonzero));
  out[0] = {v[0], e[0]};
  out[1] = {v[1], e[1]};
}

// Four polynomials per instruction.
__attribute__((target("avx2"))) void eval_four(const std::array<double, kTerms>* const* p, const Monomials& m,
                                               Bounded* out) {
  // Transpose the four rows of ten coefficients into c[i] = (p0[i], p1[i], p2[i], p3[i]).
  __m256d c[kTerms];
  for (int i0 = 0; i0 < 8; i0 += 4) {
    const __m256d r0 = _mm256_loadu_pd(p[0]->data() + i0), r1 = _mm256_loadu_pd(p[1]->data() + i0);
    const __m256d r2 = _mm256_loadu_pd(p[2]->data() + i0), r3 = _mm256_loadu_pd(p[3]->data() + i0);
    const __m256d lo01 = _mm256_unpacklo_pd(r0, r1), hi01 = _mm256_unpackhi_pd(r0, r1);
    const __m256d lo23 = _mm256_unpacklo_pd(r2, r3), hi23 = _mm256_unpackhi_pd(r2, r3);
    c[i0 + 0] = _mm256_permute2f128_pd(lo01, lo23, 0x20);
    c[i0 + 1] = _mm256_permute2f128_pd(hi01, hi23, 0x20);
    c[i0 + 2] = _mm256_permute2f128_pd(lo01, lo23, 0x31);
    c[i0 + 3] = _mm256_permute2f128_pd(hi01, hi23, 0x31);
  }
  {
    const __m256d r02 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p[0]->data() + 8)),
                                             _mm_loadu_pd(p[2]->data() + 8), 1);
    const __m256d r13 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p[1]->data() + 8)),
                                             _mm_loadu_pd(p[3]->data() + 8), 1);
    c[8] = _mm256_unpacklo_pd(r02, r13);
    c[9] = _mm256_unpackhi_pd(r02, r13);
  }
  __m256d nonzero = _mm256_setzero_pd();
  for (int i = 0; i < kTerms; ++i)
    nonzero = _mm256_or_pd(nonzero, _mm256_cmp_pd(c[i], _mm256_setzero_pd(), _CMP_NEQ_UQ));
  __m256d d[kTerms];
  for (int st = 0; st < kTerms; ++st) d[st] = _mm256_setzero_pd();
#pragma GCC unroll 35
  for (int k = 0; k < Monomials::kPairs; ++k)
    d[kPairTable.st[k]] =
        _mm256_add_pd(d[kPairTable.st[k]], _mm256_mul_pd(c[kPairTable.m[k]], _mm256_set1_pd(m.tv[k])));
  const __m256d sign = _mm256_set1_pd(-0.0);
  __m256d mag = _mm256_setzero_pd();
  for (int i = 0; i < kTerms; ++i)
    mag = _mm256_add_pd(mag, _mm256_mul_pd(_mm256_andnot_pd(sign, c[i]), _mm256_set1_pd(m.g[i])));
  __m256d err = _mm256_add_pd(_mm256_mul_pd(_mm256_set1_pd(kMagFactor), mag), _mm256_set1_pd(kSlack));
  for (int st = 1; st < kTerms; ++st)
    err = _mm256_add_pd(err, _mm256_mul_pd(_mm256_andnot_pd(sign, d[st]), _mm256_set1_pd(m.rw[st])));
  alignas(32) double v[4], e[4];
  _mm256_store_pd(v, _mm256_and_pd(d[0], nonzero));
  _mm256_store_pd(e, _mm256_and_pd(err, nonzero));
  for (int i = 0; i < 4; ++i) out[i] = {v[i], e[i]};
}

#endif

}  // namespace

void eval_polys(SimdLevel level, const std::array<double, kPoly3Terms>* const* c, int count, const Monomials& m,
                Bounded* out) {
#if defined(__x86_64__)
  if (!m.point && level != SimdLevel::scalar) {
    if (level == SimdLevel::avx2)
      for (; count >= 4; count -= 4, c += 4, out += 4) eval_four(c, m, out);
    for (; count >= 2; count -= 2, c += 2, out += 2) eval_two(*c[0], *c[1], m, out);
    if (count == 1) *out = eval_poly(*c[0], m);
    return;
  }
#else
  (void)level;
#endif
  for (int i = 0; i < count; ++i) out[i] = eval_poly(*c[i], m);
}

}  // namespace cmr::backend::box_eval
