#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
/// The outcomes of one (sub)segment's coefficients under Algorithms 1 and 2
/// (CAD&A 2024 §3). A public header of its own, free of the scalar types
/// (no GMP, no __int128), so that analysis headers can name it.
#include <cstdint>

namespace cmr {

/// What one (sub)segment's coefficients say under Algorithms 1 and 2; every
/// implementation of the traversal (generic, fast, regions, the shader)
/// decides pieces into these outcomes and folds them the same way.
///
/// Not Curvature (classify.hpp): a Piece is one step's outcome inside the
/// traversal (zero, inflection / no_inflection, split: "subdivide further",
/// uncertain: "a bound straddles 0, ask the exact path"), a Curvature the
/// folded verdict of a whole segment (constant, non_monotone, undecided at
/// the depth limit). The folds of decide.hpp map one onto the other.
enum class Piece : std::uint8_t { increasing, decreasing, zero, non_monotone, inflection, no_inflection, split, uncertain };

const char* to_string(Piece p);

}  // namespace cmr
