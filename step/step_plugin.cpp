// The module cmr_step_plugin.so: the OpenCASCADE importer (step_occt.cpp,
// linked in with OCCT) behind one exported entry point (step_plugin.hpp).
#include "step/step_plugin.hpp"

extern "C" __attribute__((visibility("default"))) const cmr::import::StepPlugin* cmr_step_plugin_entry() {
  static const cmr::import::StepPlugin plugin{cmr::import::kStepPluginAbi, &cmr::import::read_step_curves,
                                              &cmr::import::step_chain_junctions};
  return &plugin;
}
