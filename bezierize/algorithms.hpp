#pragma once
/// Algorithms 1 and 2 on Bernstein coefficients of any scalar type (double,
/// Bounded, Rational). Internal: it needs the scalar types (GMP, __int128),
/// which the public analysis headers (classify.hpp, analyze.hpp, region.hpp)
/// keep out of users' translation units.
#include <optional>

#include "numeric/bernstein.hpp"
#include "bezierize/classify.hpp"

namespace cmr {

/// Algorithm 1 on xi. nullopt when T carries error bounds and a sign that
/// decides the outcome is uncertain (then rerun exactly).
template <class T>
std::optional<MonotonicityResult> algorithm1(const Bernstein<T>& xi, int max_depth);
/// Algorithm 2 on nu, with the same convention.
template <class T>
std::optional<InflectionResult> algorithm2(const Bernstein<T>& nu, int max_depth);

}  // namespace cmr
