#pragma once
/// The one JSON writer of a Joint (analyze.hpp), behind the "joints" arrays
/// of `cmr analyze` and of the report (cmr-report/2, docs/report-schema.md).
/// The two documents share every field of a joint; each adds marks of its
/// own, so both stay as they were:
///   index, knot, multiplicity, continuity ("C<k>"), g1, g2, angle (degrees;
///   NaN at a zero tangent prints as null), zero_tangent, [corner],
///   kappa_left, kappa_right, jump ("up", "down", "none"), [pole], [seam].
#include <optional>

#include <nlohmann/json.hpp>

#include "bezierize/analyze.hpp"

namespace cmr {

/// Which optional fields joint_json writes.
struct JointJsonFields {
  std::optional<bool> corner;  ///< "corner" with this value (the report's: not G1)
  bool marks = false;   ///< "pole": true where W = 0 at the knot, "seam": true on `seam` (analyze's)
  bool seam = false;    ///< with marks: this joint is a closed spline's seam
};

nlohmann::ordered_json joint_json(const Joint& joint, const JointJsonFields& fields = {});

}  // namespace cmr
