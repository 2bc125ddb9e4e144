#pragma once
/// Limits and defaults that several modules, the CLI and the shader build
/// share. Each is written once, here.
#include <cstddef>

namespace cmr {

/// D of Algorithms 1 and 2 when the user gives none (CAD&A 2024 §3 uses 12).
inline constexpr int kDefaultDepth = 12;
/// Deepest subdivision level accepted anywhere: the fixed-size traversal
/// stacks hold kMaxDepth + 2 pieces, and a piece at level 30 spans 2^-30.
inline constexpr int kMaxDepth = 30;
/// Highest B-spline degree accepted: the exact binomial weights of λ
/// (degree 4n−7) are kept in 128-bit integers, which hold C(4n−7, k) up to n = 30.
inline constexpr int kMaxDegree = 30;
/// Largest input file read (spline, points or script file): 64 MiB, far
/// above any real curve (a 64 MiB spline holds about a million points), so
/// that a huge or endless file fails at once instead of filling memory.
inline constexpr std::size_t kMaxInputBytes = std::size_t{64} << 20;

}  // namespace cmr
