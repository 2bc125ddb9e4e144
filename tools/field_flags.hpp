#pragma once
// The libraries speak in fields, not flags (spline/fields.hpp): a message
// names an option by its request field, marked. The cmr command (and its
// editor) shows each marked field as the flag that sets it, through the one
// table below, so the command's lines read as they always have.
#include <exception>
#include <map>
#include <string>

#include "spline/fields.hpp"

namespace cmr::cli {

/// Each library field and the flag that sets it: the one place the command
/// names the libraries' option fields. A field not listed shows by its name.
/// Fields of two requests that two flags set are qualified by their request
/// (WeightRegionRequest::point is --weight, SpaceRegionRequest's point --point).
inline const std::map<std::string, std::string>& field_flags() {
  static const std::map<std::string, std::string> flags = {
      {"WeightRegionRequest::point", "--weight"},
      {"angle_deg", "--angle-tol"},
      {"backend", "--backend"},
      {"baseline", "--baseline"},
      {"between", "--between"},
      {"add_nodes", "--add-nodes"},
      {"contours", "--contours"},
      {"conventional", "--conventional"},
      {"curvature_rel", "--curvature-tol"},
      {"each_piece", "--each-piece"},
      {"edges", "--edges"},
      {"exclude", "--exclude"},
      {"fix_budget", "--fix-budget"},
      {"from", "--from"},
      {"glyph", "--glyph"},
      {"glyph_work", "--work"},
      {"glyphs", "--glyphs"},
      {"grid", "--grid"},
      {"in_place", "--in-place"},
      {"include", "--include"},
      {"keep", "--keep"},
      {"location", "--location"},
      {"max_depth", "--depth"},
      {"max_move", "--max-move"},
      {"max_seconds", "--max-seconds"},
      {"min_severity", "--min-severity"},
      {"no_severity", "--no-severity"},
      {"mesh", "--mesh"},
      {"out", "--out"},
      {"parts", "--merge"},
      {"plane", "--plane"},
      {"point", "--point"},
      {"points", "--points"},
      {"precision", "--precision"},
      {"radius", "--tube-radius"},
      {"require", "--require"},
      {"requirement", "--require"},
      {"samples", "--samples"},
      {"segments", "--segments"},
      {"shard", "--shard"},
      {"size", "--size"},
      {"source_root", "--source-root"},
      {"split", "--split"},
      {"strict", "--strict"},
      {"time_limit", "--time-limit"},
      {"to", "--to"},
      {"tolerance", "--tolerance"},
      {"torsion_tolerance", "--torsion-tol"},
      {"view", "--view"},
      {"with", "--with"},
  };
  return flags;
}

/// A library message as the command shows it: each field it names as the
/// flag that sets it, e.g. "with point 3 is named twice" as "--with point 3
/// is named twice". Text without marks comes back as it is.
inline std::string show_fields(const std::string& marked) {
  return rename_fields(marked, [](const std::string& name) {
    const auto it = field_flags().find(name);
    return it != field_flags().end() ? it->second : name;
  });
}

/// The message of `e` so shown (its marked text where it names fields).
inline std::string shown_message(const std::exception& e) { return show_fields(marked_text(e)); }

}  // namespace cmr::cli
