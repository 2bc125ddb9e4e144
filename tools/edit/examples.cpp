#include "tools/edit/examples.hpp"

#include <nlohmann/json.hpp>

#include "spline/spline_json.hpp"
#include "tools/edit/fig8_json.hpp"

namespace cmr::edit {

BSpline fig8_spline() { return spline_from_json(nlohmann::json::parse(kFig8Json)); }

}  // namespace cmr::edit
