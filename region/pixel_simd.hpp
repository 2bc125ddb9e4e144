#pragma once
// Internal to cmr::region and the libraries above it: a library user includes
// `region/region.hpp` (space curves: `region/space_region.hpp`).
// SIMD across pixels for the CPU region render's per-pixel kernel (issue 23,
// item 2): the root values of one touched segment,
//     v[c] = sum_m t[m * n1 + c] mu_m(dx, dy),   m = 0, 1, ..., 9 in that order,
// and the one bound of all of them,
//     E = units * sum_m mag[m] |mu_m| + tiny16,
// for a chunk of pixels at once: 4 with AVX2 (4 doubles per instruction), 2
// with SSE2, 1 in plain C++. Every level does the same IEEE operations in
// the same order (separate multiplies and adds, no FMA contraction: the AVX2
// code is compiled with target("avx2") only), so v and E are bit-identical
// at every level, and so are the labels and depths that region.cpp derives
// from them (tests/region/pixel_simd_test.cpp checks both).
//
// The level is the best the CPU has (__builtin_cpu_supports("avx2"), else
// SSE2, the x86-64 baseline; scalar on other architectures), unless
// set_simd_level forces one. The library reads no environment: cmr and the
// benchmarks read CMR_SIMD=scalar|sse2|avx2 at start (tools/cli_common.hpp
// read_environment, with simd_level_for); an unknown value, or a level this
// CPU or build lacks, prints one line on stderr and the best level is used.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace cmr::backend {

enum class SimdLevel { scalar = 0, sse2 = 1, avx2 = 2 };

/// "scalar", "sse2", "avx2".
const char* simd_name(SimdLevel level);
/// Pixels per instruction: 1, 2, 4.
int simd_lanes(SimdLevel level);
/// Whether this build and CPU can run `level` (scalar: always).
bool simd_available(SimdLevel level);
/// The best available level.
SimdLevel best_simd_level();
/// A CMR_SIMD value: nullopt unless exactly "scalar", "sse2" or "avx2".
std::optional<SimdLevel> parse_simd_level(std::string_view text);
/// The level for CMR_SIMD's value `env` (nullptr or empty: unset): the named
/// level, or the best one with `warning` set to the line to print when the
/// value is unknown or the level unavailable.
SimdLevel simd_level_for(const char* env, std::string& warning);
/// The level the CPU render uses: set_simd_level's if called, else the best.
SimdLevel simd_level();
/// Forces the level of later renders (tests, benchmarks); false (and the level
/// unchanged) when this CPU or build lacks it.
bool set_simd_level(SimdLevel level);

/// The root values and bound of one kernel entry (kernel.hpp's PixelKernel:
/// t monomial-major, t[m * n1 + c]; mag[m] = max_c |t[m * n1 + c]|) for the
/// simd_lanes(level) pixels with displacements dx[0..], dy[0..]: pixel p's
/// value c goes to v[c * stride + p], its bound to e[p].
void pixel_root_values(SimdLevel level, const double* t, const double* mag, int n1, const double* dx,
                       const double* dy, double* v, int stride, double* e, double units, double tiny);

/// Pixels whose root values went through pixel_root_values at each level,
/// so tests can see that a comparison covers pixels of the batch path.
/// count_simd_pixels adds to the calling thread's own tally (no shared cache
/// line touched per chunk of lanes); publish_simd_pixel_counts adds that
/// tally to the totals simd_pixel_count reads (block.cpp: once per 64x64
/// block job).
std::uint64_t simd_pixel_count(SimdLevel level);
void count_simd_pixels(SimdLevel level, int pixels);
void publish_simd_pixel_counts();

/// Test hook: when on, the SIMD levels (not scalar) negate lane 1's v[0], so
/// a test can check that its comparison catches a wrong batch.
void set_simd_fault_for_test(bool on);

}  // namespace cmr::backend
