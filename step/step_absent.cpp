// The STEP importer of a build without OpenCASCADE (step/CMakeLists.txt).
#include "spline/errors.hpp"
#include "step/step.hpp"

namespace cmr::import {

bool step_supported() { return false; }

StepCurves read_step_curves(const std::filesystem::path& path, const ChainTolerances&) {
  throw InputError(path.string() +
                   ": cmr was built without STEP support (OpenCASCADE was not found when it was configured; "
                   "tools/setup.sh installs it)");
}

std::vector<StepJunction> step_chain_junctions(const StepCurves&, const StepChain&, const ChainTolerances&) {
  throw InputError("cmr was built without STEP support (OpenCASCADE was not found when it was configured; "
                   "tools/setup.sh installs it)");
}

}  // namespace cmr::import
