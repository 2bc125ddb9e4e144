#pragma once
// Shared by the harnesses: the input as JSON, and a spline from it.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "spline/errors.hpp"
#include "spline/spline_json.hpp"

namespace cmr::fuzz {

/// The bytes as a spline file, or nothing when they are not one (the
/// reader's InputError is the expected answer to bad data).
inline std::optional<BSpline> spline_from_bytes(const std::uint8_t* data, std::size_t size, bool conventional = false) {
  const nlohmann::json doc = nlohmann::json::parse(data, data + size, nullptr, false);
  if (doc.is_discarded()) return std::nullopt;
  try {
    return spline_from_json(doc, {.conventional = conventional});
  } catch (const InputError&) {
    return std::nullopt;
  }
}

/// Work bounds so that one input stays fast (the CLI's own limits are larger).
inline bool small_enough(const BSpline& s) { return s.point_count() <= 24 && s.degree() <= 7; }

}  // namespace cmr::fuzz
