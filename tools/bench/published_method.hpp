#pragma once
/// The benchmark's baseline: curvature monotonicity regions computed as their
/// authors implemented them (Yoshida et al., CAD&A 21(1) 2024, §3-4): per
/// pixel, control point k moves to the pixel centre, the touched Bézier
/// segments get their new points (B_i = B0_i + w_i (p - P_k), B0 and w
/// computed once per image on the CPU, as the authors' tool hands points to
/// its shader), λ's Bernstein coefficients ξ_0..ξ_{4n-7} come from
/// straight-line code of the segment's fixed degree, and Algorithm 1 runs
/// depth first on a fixed-size stack, in plain double: no error bounds, no
/// exact fallback, no block culling, no heap allocation per pixel. Rows are
/// jobs on every core (cmr::parallel_for).
///
/// It uses only the spline layer (BSpline, bezier_segments, influence) and
/// the one pixel→world map (pixel_center); nothing of cmr's region engine.
///
/// Scope: CMRWI mode (every segment monotone in one common direction), one
/// moved point, degrees kPublishedMinDegree..kPublishedMaxDegree, splines
/// that are C² at every joint (no curvature jumps to judge).
/// Labels are the region labels of `cmr region` (0 not monotone,
/// 1 increasing, 2 decreasing, 3 undecided at the depth limit), so the two
/// can be compared pixel by pixel; the paper counts 3 as not monotone.
///
/// ξ by fixed degree n (see bezierize/lambda.hpp for the derivation): with the
/// hodograph q_i = n (P_{i+1} - P_i), i = 0..m = n-1,
///   η = det(P', P'') at degree 2n-4:
///     C(2n-4,k) ν_k = Σ_{i<j, i+j-1=k} (j-i) C(m,i) C(m,j) det(q_i, q_j),
///   g = P'·P' at degree 2n-2:
///     C(2n-2,k) g_k = Σ_{i≤j, i+j=k} (i=j ? 1 : 2) C(m,i) C(m,j) q_i·q_j,
///   λ = η' g - (3/2) η g' at degree 4n-7, with η'_k = (2n-4)(ν_{k+1} - ν_k),
///   g'_k = (2n-2)(g_{k+1} - g_k) and the Bernstein product written on
///   binomially scaled coefficients (F_i = C(p,i) f_i):
///     C(p+r,k) (f h)_k = Σ_{i+j=k} F_i H_j.
/// Every binomial is a compile-time constant and every loop bound a
/// compile-time constant, so the compiler emits straight-line code per degree.
/// Per pixel, condition (3) at level 0 is tested first on ξ_0 and ξ_{4n-7}
/// alone (each from four points), so most pixels outside a region never form
/// the full ξ.
#include <array>
#include <cstdint>
#include <vector>

#include "region/region.hpp"
#include "spline/bspline.hpp"

namespace cmr::bench {

inline constexpr int kPublishedMinDegree = 3;
inline constexpr int kPublishedMaxDegree = 9;

/// One region image for the baseline.
struct PublishedRegion {
  int point = 0;        ///< k: the control point placed at each pixel
  int max_depth = 12;   ///< D of Algorithm 1 (level 0 = whole segment)
  int width = 512, height = 512;
  View view;            ///< world rectangle (pixel_center maps pixels into it)
  int threads = 0;      ///< 0: every core
};

/// Labels of every pixel, row-major, row 0 at the top. Throws InputError for
/// a degree outside kPublishedMinDegree..kPublishedMaxDegree, a joint that is
/// not C², a point out of range, a size outside 1..kMaxImageSize or a depth
/// outside 0..kMaxDepth.
std::vector<uint8_t> published_region(const BSpline& spline, const PublishedRegion& request);

/// The same labels by the same arithmetic, vectorised across pixels: kLanes
/// (4) pixels of a row per step (GCC vector extensions; with AVX2, where
/// tools/bench/CMakeLists.txt finds it, 4 doubles per instruction). ξ and the
/// level-0 rules are computed for the 4 pixels at once; then either
/// (lockstep) each lane runs its own depth-first Algorithm 1 on a fixed
/// stack, all lanes' pieces halved by one vector de Casteljau per step and
/// lanes masked out as they finish, as a fragment shader runs it, or
/// (default) the lanes that must split continue one by one. Same errors as
/// published_region; labels equal to it byte for byte (the same operations
/// in the same order per pixel, no FMA contraction).
std::vector<uint8_t> published_region_lanes(const BSpline& spline, const PublishedRegion& request,
                                            bool lockstep = false);

/// What a device running the baseline needs from the host (the authors' tool
/// likewise hands points to its shader): per moved segment, for each of its
/// n+1 points, base x, base y and weight w (B = base + w (p - P_k)), and the
/// directions of the untouched segments (bit 0 increasing, bit 1
/// decreasing, bit 2 undecided). all_zero: an untouched segment already
/// fails, so every label is 0. Validates as published_region does.
struct PublishedHostPart {
  int degree = 0;
  Vec2 anchor;
  int segments = 0;
  std::vector<double> data;
  uint32_t fixed_directions = 0;
  bool all_zero = false;
};
PublishedHostPart published_host_part(const BSpline& spline, const PublishedRegion& request);

/// ξ_0..ξ_{4n-7} of the Bézier segment with points P (n = P.size()-1) by the
/// baseline's fixed-degree code, for tests. Throws InputError for a degree
/// outside kPublishedMinDegree..kPublishedMaxDegree.
std::vector<double> published_lambda(const std::vector<Vec2>& P);

/// ξ_0 and ξ_{4n-7} alone, as the baseline forms them for its level-0
/// rejection before the full ξ (same degrees, same errors).
std::array<double, 2> published_lambda_ends(const std::vector<Vec2>& P);

}  // namespace cmr::bench
