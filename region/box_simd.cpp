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

// W doubles per instruction (GCC vector extensions, as pixel_lanes.hpp):
// W = 2 is SSE2, the x86-64 baseline; W = 4 is inlined into an AVX2
// function below, where it compiles to 256-bit instructions.
template <int W>
struct LaneTypes;
template <>
struct LaneTypes<2> {
  typedef double Values __attribute__((vector_size(16)));
  typedef long long Bits __attribute__((vector_size(16)));
};
template <>
struct LaneTypes<4> {
  typedef double Values __attribute__((vector_size(32)));
  typedef long long Bits __attribute__((vector_size(32)));
};
template <int W>
using Lanes = typename LaneTypes<W>::Values;

// eval_poly's arithmetic on W polynomials at once, their coefficients
// transposed: c[i][l] is coefficient i of polynomial l. Each lane does the
// scalar code's multiplies and adds in its order.
template <int W>
[[gnu::always_inline]] inline void eval_lanes(const Lanes<W>* c, const Monomials& m, Bounded* out) {
  using V = Lanes<W>;
  using Bits = typename LaneTypes<W>::Bits;
  const Bits magnitude = Bits{} + 0x7fffffffffffffffLL;  // |x| as fabs gives it: every bit but the sign
  V abs_c[kTerms];
  for (int i = 0; i < kTerms; ++i) abs_c[i] = reinterpret_cast<V>(reinterpret_cast<Bits>(c[i]) & magnitude);
  Bits nonzero = c[0] != 0;  // NaN counts as non-zero, as in eval_poly's test
  for (int i = 1; i < kTerms; ++i) nonzero |= c[i] != 0;
  V d[kTerms] = {};
#pragma GCC unroll 35
  for (int k = 0; k < Monomials::kPairs; ++k)
    d[kPairTable.st[k]] = d[kPairTable.st[k]] + c[kPairTable.m[k]] * m.tv[k];
  V mag = {};
  for (int i = 0; i < kTerms; ++i) mag = mag + abs_c[i] * m.g[i];
  V err = kMagFactor * mag + kSlack;
  for (int st = 1; st < kTerms; ++st)
    err = err + reinterpret_cast<V>(reinterpret_cast<Bits>(d[st]) & magnitude) * m.rw[st];
  // An all-zero polynomial is exactly zero (eval_poly's first test).
  for (int l = 0; l < W; ++l) out[l] = nonzero[l] ? Bounded{d[0][l], err[l]} : Bounded{0.0, 0.0};
}

// Two polynomials per instruction (SSE2).
void eval_two(const std::array<double, kTerms>* const* p, const Monomials& m, Bounded* out) {
  Lanes<2> c[kTerms];
  for (int i = 0; i < kTerms; ++i) c[i] = Lanes<2>{(*p[0])[i], (*p[1])[i]};
  eval_lanes<2>(c, m, out);
}

// Four polynomials per instruction. target("avx2") only: no FMA, so the
// compiler cannot contract a multiply and an add into one rounding.
__attribute__((target("avx2"))) void eval_four(const std::array<double, kTerms>* const* p, const Monomials& m,
                                               Bounded* out) {
  // Transpose the four rows of ten coefficients into c[i] = (p0[i], p1[i], p2[i], p3[i]).
  Lanes<4> c[kTerms];
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
  const __m256d r02 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p[0]->data() + 8)),
                                           _mm_loadu_pd(p[2]->data() + 8), 1);
  const __m256d r13 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p[1]->data() + 8)),
                                           _mm_loadu_pd(p[3]->data() + 8), 1);
  c[8] = _mm256_unpacklo_pd(r02, r13);
  c[9] = _mm256_unpackhi_pd(r02, r13);
  eval_lanes<4>(c, m, out);
}

#endif

}  // namespace

void eval_polys(SimdLevel level, const std::array<double, kPoly3Terms>* const* c, int count, const Monomials& m,
                Bounded* out) {
#if defined(__x86_64__)
  if (!m.point && level != SimdLevel::scalar) {
    if (level == SimdLevel::avx2)
      for (; count >= 4; count -= 4, c += 4, out += 4) eval_four(c, m, out);
    for (; count >= 2; count -= 2, c += 2, out += 2) eval_two(c, m, out);
    if (count == 1) *out = eval_poly(*c[0], m);
    return;
  }
#else
  (void)level;
#endif
  for (int i = 0; i < count; ++i) out[i] = eval_poly(*c[i], m);
}

}  // namespace cmr::backend::box_eval
