#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.
// isolate_roots (numeric/roots.hpp) on error-bounded coefficients: the same
// halving, Descartes counts and bisection, step for step, with every sign
// decided from a certified double (numeric/bounded.hpp) instead of a
// rational. When every sign the exact algorithm reads is certain the result
// is exactly the one isolate_roots gives on the exact coefficients (the
// algorithm is deterministic in those signs); the first uncertain sign gives
// up (nullopt) and the caller runs the exact isolation. Multiple roots inside
// (square-free split) and zeros that are not exact in double always give up.
#include <cstdint>
#include <optional>
#include <vector>

#include "numeric/bernstein.hpp"
#include "numeric/fast_path.hpp"
#include "numeric/roots.hpp"

namespace cmr {

/// One root as isolate_roots returns it, with dyadic ends: lo = k / 2^level,
/// hi = lo (exact) or (k + 1) / 2^level.
struct FastRoot {
  std::uint64_t k = 0;
  int level = 0;
  bool exact = false;
  int multiplicity = 1;
  int sign_before = 0, sign_after = 0;
  double lo() const { return std::ldexp(static_cast<double>(k), -level); }
  double hi() const { return exact ? lo() : std::ldexp(static_cast<double>(k + 1), -level); }
  double mid() const { return exact ? lo() : std::ldexp(static_cast<double>(2 * k + 1), -level - 1); }
};

/// p's coefficients each enclose the exact one (|exact - v| <= e). nullopt
/// when a sign that the exact isolation reads is uncertain. Otherwise equal
/// to isolate_roots(exact p, options), root for root.
std::optional<std::vector<FastRoot>> isolate_roots_bounded(const Bernstein<Bounded>& p, const RootOptions& options);

/// The sign of p just right of 0 (its first non-zero coefficient), kSignUnknown
/// when that is not certain.
int sign_at_start_bounded(const Bernstein<Bounded>& p);

}  // namespace cmr
