#pragma once
/// `cmr fix`'s JSON document (docs/fix.md) from a finished fix: the moves,
/// the units tried, the certificate (the fixed curve re-judged by analyze,
/// as `cmr analyze` prints its verdicts) and the counts. One writer for the
/// command (tools/cmd_fix.cpp, which adds "out" and "png") and the Python
/// module (python/cmr_module.cpp).
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "design/fix.hpp"
#include "design/space_fix.hpp"

namespace cmr::report {

/// The document of `f`, the answer to `request`; "file" comes first when
/// given (the command names its input file; the Python module has none).
nlohmann::ordered_json fix_json(const std::optional<std::string>& file, const FixRequest& request, const FixResult& f);

/// The same for a space curve's fix (docs/fix.md, "Space curves"): 3D
/// moves with their planes, "dimension": 3, "joint_conflicts", and the
/// certificate's verdict of `cmr analyze` (analyze_space). `require` is
/// "cmr" or "cmrwi" as given.
nlohmann::ordered_json space_fix_document(const std::optional<std::string>& file, const std::string& require,
                                          const SpaceFixRequest& request, const SpaceFixResult& f);

}  // namespace cmr::report
