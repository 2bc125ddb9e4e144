#include "bezierize/joint_json.hpp"

#include <string>

namespace cmr {

nlohmann::ordered_json joint_json(const Joint& j, const JointJsonFields& fields) {
  std::string continuity = "C";  // built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + string
  continuity += std::to_string(j.continuity);
  nlohmann::ordered_json out = {{"index", j.index},
                                {"knot", j.knot},
                                {"multiplicity", j.multiplicity},
                                {"continuity", continuity},
                                {"g1", j.g1},
                                {"g2", j.g2},
                                {"angle", j.angle_deg},  // NaN (a zero tangent) prints as null
                                {"zero_tangent", j.zero_tangent}};
  if (fields.corner) out["corner"] = *fields.corner;
  out["kappa_left"] = j.kappa_left;
  out["kappa_right"] = j.kappa_right;
  out["jump"] = jump_name(shown_jump(j));  // "none" at a G2 joint (docs/semantics.md)
  out["exact_jump"] = jump_name(j.jump);   // the exact sign of the jump
  if (fields.marks && j.pole) out["pole"] = true;
  if (fields.marks && fields.seam) out["seam"] = true;
  return out;
}

}  // namespace cmr
