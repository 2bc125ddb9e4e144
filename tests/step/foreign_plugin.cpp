// A module with the STEP plugin's entry point but another interface version:
// cmr must refuse it (step/step_load.cpp), not call through it.
#include <cstdint>

struct ForeignPlugin {
  std::uint64_t abi;
  void* functions[2];
};

extern "C" __attribute__((visibility("default"))) const ForeignPlugin* cmr_step_plugin_entry() {
  static const ForeignPlugin plugin{1, {nullptr, nullptr}};
  return &plugin;
}
