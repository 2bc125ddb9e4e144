#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
/// The one JSON writer of a Joint (analyze.hpp), behind the "joints" arrays
/// of `cmr analyze` and of the report (cmr-report/2, docs/report-schema.md).
/// The two documents share every field of a joint; each adds marks of its
/// own, so both stay as they were:
///   index, knot, multiplicity, continuity ("C<k>"), g1, g2, angle (degrees;
///   NaN at a zero tangent prints as null), zero_tangent, [corner],
///   kappa_left, kappa_right, jump ("up", "down", "none"), [pole], [seam].
#include <optional>
#include <string>

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

/// The members of joint_json(j, fields), in the same order, written into an
/// open object of any writer with report::JsonStream's interface (key,
/// value, member): the text stream, or the Python module's dict builder.
/// tests/report/json_stream_test.cpp holds the two to the same text.
template <class Out>
void write_joint_members(Out& o, const Joint& j, const JointJsonFields& fields = {}) {
  o.member("index", j.index);
  o.member("knot", j.knot);
  o.member("multiplicity", j.multiplicity);
  std::string continuity = "C";  // built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + string
  continuity += std::to_string(j.continuity);
  o.member("continuity", continuity);
  o.member("g1", j.g1);
  o.member("g2", j.g2);
  o.member("angle", j.angle_deg);  // NaN (a zero tangent) prints as null
  o.member("zero_tangent", j.zero_tangent);
  if (fields.corner) o.member("corner", *fields.corner);
  o.member("kappa_left", j.kappa_left);
  o.member("kappa_right", j.kappa_right);
  o.member("jump", jump_name(shown_jump(j)));  // "none" at a G2 joint (docs/semantics.md)
  o.member("exact_jump", jump_name(j.jump));   // the exact sign of the jump
  if (fields.marks && j.pole) o.member("pole", true);
  if (fields.marks && fields.seam) o.member("seam", true);
}

}  // namespace cmr
