#pragma once
/// The STEP importer's plugin interface (internal to cmr::step). In a build
/// with OpenCASCADE, cmr's programs do not link OCCT: its libraries cost
/// every start about 17 ms of dynamic linking and static initialisation
/// (docs/space.md, "OpenCASCADE loads only for STEP"), whether or not a STEP
/// file is read. The
/// importer (step_occt.cpp) is built into the module cmr_step_plugin.so
/// (step_plugin.cpp) instead, and step_load.cpp loads it the first time
/// read_step_curves or step_chain_junctions is called.
#include <cstdint>
#include <vector>

#include "step/step.hpp"

namespace cmr::import {

/// The functions the plugin hands over. Both sides are built from the same
/// tree; kStepPluginAbi changes with the layout of what crosses, so a stale
/// plugin is refused instead of misread.
struct StepPlugin {
  std::uint64_t abi;
  StepCurves (*read_step_curves)(const std::filesystem::path& path, const ChainTolerances& chains);
  std::vector<StepJunction> (*step_chain_junctions)(const StepCurves& curves, const StepChain& chain,
                                                     const ChainTolerances& tolerances);
};

/// Interface version 1, and the sizes of the types that cross.
inline constexpr std::uint64_t kStepPluginAbi =
    (std::uint64_t{1} << 56) ^ (std::uint64_t{sizeof(StepCurves)} << 40) ^
    (std::uint64_t{sizeof(StepCurve)} << 24) ^ (std::uint64_t{sizeof(StepChain)} << 12) ^
    std::uint64_t{sizeof(StepJunction)} ^ (std::uint64_t{sizeof(ChainTolerances)} << 6);

/// The plugin's one exported symbol.
inline constexpr const char* kStepPluginEntry = "cmr_step_plugin_entry";
using StepPluginEntry = const StepPlugin* (*)();

}  // namespace cmr::import
