#pragma once
/// `cmr fix`'s JSON document (docs/fix.md) from a finished fix: the moves,
/// the units tried, the certificate (the fixed curve re-judged by analyze,
/// as `cmr analyze` prints its verdicts) and the counts. One writer for the
/// command (tools/cmd_fix.cpp, which adds "out" and "png") and the Python
/// module (python/cmr_module.cpp).
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "bezierize/fix.hpp"

namespace cmr::report {

/// The document of `f`, the answer to `request`; "file" comes first when
/// given (the command names its input file; the Python module has none).
nlohmann::ordered_json fix_json(const std::optional<std::string>& file, const FixRequest& request, const FixResult& f);

}  // namespace cmr::report
