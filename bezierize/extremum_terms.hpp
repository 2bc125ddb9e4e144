#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
/// The designer's reading of a curvature extremum (docs/semantics.md,
/// "Sharpest and flattest"): by |kappa|, which does not depend on the
/// direction of travel or on mirroring, instead of by signed kappa, which
/// does (reversing the parameter or mirroring x -> -x negates kappa, so a
/// signed maximum becomes a signed minimum; a TrueType outer contour runs
/// clockwise, a CFF one counter-clockwise).
///
///  * sharpest: |kappa| has a local maximum there (the comb is longest);
///  * flattest: |kappa| has a local minimum there (the comb is shortest),
///    including a point where kappa touches 0 without changing sign;
///  * inflection: kappa changes sign there (|kappa| falls to 0 or jumps
///    across it): an extremum of signed kappa at a joint whose two sides
///    have opposite curvature signs (or zero curvature on one side) is
///    neither sharpest nor flattest; it is called an inflection.
///
/// From the signed reading: a signed maximum (kappa rises, then falls) where
/// kappa > 0 on both sides is sharpest, where kappa < 0 on both sides
/// flattest; a signed minimum the other way round; kappa = 0 on both sides
/// (a touching zero) is flattest. The signs come from certified
/// curvatures (exact signs: analyze.hpp, Joint::kappa_left/right).
#include <cstdint>

#include "bezierize/analyze.hpp"

namespace cmr {

enum class ExtremumKind : std::uint8_t { sharpest, flattest, inflection };

/// "sharpest", "flattest", "inflection".
inline const char* to_string(ExtremumKind k) {
  switch (k) {
    case ExtremumKind::sharpest: return "sharpest";
    case ExtremumKind::flattest: return "flattest";
    case ExtremumKind::inflection: return "inflection";
  }
  return "?";
}

inline int sign_of(double v) { return v > 0 ? 1 : (v < 0 ? -1 : 0); }

/// The |kappa| reading of an extremum of signed kappa: `signed_kind` +1 for a
/// maximum of kappa, -1 for a minimum; `sign_left`, `sign_right` the exact
/// signs of kappa on its two sides (equal inside a segment).
constexpr ExtremumKind extremum_kind(int signed_kind, int sign_left, int sign_right) {
  if (sign_left == 0 && sign_right == 0) return ExtremumKind::flattest;  // kappa touches 0
  if (sign_left != sign_right) return ExtremumKind::inflection;
  return signed_kind * sign_left > 0 ? ExtremumKind::sharpest : ExtremumKind::flattest;
}

/// The |kappa| reading of a split verdict at joint `joint` (inc-dec: a signed
/// maximum there, dec-inc: a signed minimum), from the joint's certified
/// curvatures; nothing for inc-inc, dec-dec, none or undecided (no extremum
/// at the joint), or where a side's curvature is undefined (NaN: a zero
/// tangent or a pole).
inline std::optional<ExtremumKind> split_extremum_kind(Split verdict, const Joint& joint) {
  if (verdict != Split::inc_dec && verdict != Split::dec_inc) return std::nullopt;
  if (!(joint.kappa_left == joint.kappa_left) || !(joint.kappa_right == joint.kappa_right)) return std::nullopt;
  return extremum_kind(verdict == Split::inc_dec ? 1 : -1, sign_of(joint.kappa_left), sign_of(joint.kappa_right));
}

}  // namespace cmr
