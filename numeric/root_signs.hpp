// The signs of a polynomial on both sides of each of its roots, walking the
// roots left to right (the one rule of roots.cpp's exact isolation and
// fast_roots.cpp's certified float isolation).
#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.

#include <utility>

namespace cmr {

/// `sign` is p's sign just right of the previous root (for the first root:
/// p's sign at t = 0+) and becomes p's sign after this root. An odd
/// multiplicity flips it, an even one keeps it. A root exactly at t = 0
/// (`at_start`) comes before that sign: p has `sign` after it, and before it
/// (left of 0) `sign` flipped by the multiplicity. Returns {before, after}.
inline std::pair<int, int> signs_around_root(int& sign, int multiplicity, bool at_start) {
  const int flip = multiplicity % 2 == 1 ? -1 : 1;
  if (at_start) return {sign * flip, sign};
  const int before = sign;
  sign *= flip;
  return {before, sign};
}

}  // namespace cmr
