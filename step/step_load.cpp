// The STEP importer of cmr's programs in a build with OpenCASCADE: the
// plugin cmr_step_plugin.so (step_plugin.hpp says why), loaded at the first
// read. It is looked for relative to the running program's folder: where
// `cmake --install` puts it (CMR_STEP_PLUGIN_FROM_BIN, ../lib/cmr/ or
// similar), then beside the program (the build tree). No absolute path is
// built in, so an installed cmr names no folder of the build machine.
#include <dlfcn.h>

#include <filesystem>
#include <string>
#include <system_error>

#include "spline/errors.hpp"
#include "step/step_plugin.hpp"

namespace cmr::import {

namespace {

struct Loaded {
  const StepPlugin* plugin = nullptr;
  std::string error;  ///< why there is none
};

// The plugin, once per process (a failed load is not retried).
const Loaded& loaded() {
  static const Loaded once = [] {
    Loaded l;
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) {
      l.error = "cannot find the running program (/proc/self/exe: " + ec.message() + ")";
      return l;
    }
    const std::filesystem::path candidates[] = {(self.parent_path() / CMR_STEP_PLUGIN_FROM_BIN).lexically_normal(),
                                                self.parent_path() / "cmr_step_plugin.so"};
    std::string tried;
    for (const std::filesystem::path& path : candidates) {
      if (!std::filesystem::exists(path, ec)) {
        tried += (tried.empty() ? "" : ", ") + path.string();
        continue;
      }
      // Never closed: OpenCASCADE keeps state for the life of the process.
      void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!handle) {
        // dlerror says "PATH: why"; the path is said once.
        const char* e = ::dlerror();
        std::string why = e ? e : "unknown error";
        if (why.rfind(path.string() + ": ", 0) == 0) why.erase(0, path.string().size() + 2);
        l.error = path.string() + " cannot be loaded: " + why;
        return l;
      }
      const auto entry = reinterpret_cast<StepPluginEntry>(::dlsym(handle, kStepPluginEntry));
      const StepPlugin* p = entry ? entry() : nullptr;
      if (!p || p->abi != kStepPluginAbi) {
        l.error = path.string() + " is not this cmr's STEP plugin (rebuild cmr)";
        return l;
      }
      l.plugin = p;
      return l;
    }
    l.error = "its plugin is missing (looked for " + tried + "; rebuild or reinstall cmr)";
    return l;
  }();
  return once;
}

const StepPlugin& plugin() {
  const Loaded& l = loaded();
  if (!l.plugin) throw EnvironmentError("the STEP importer: " + l.error);
  return *l.plugin;
}

}  // namespace

bool step_supported() { return true; }

StepCurves read_step_curves(const std::filesystem::path& path, const ChainTolerances& chains) {
  return plugin().read_step_curves(path, chains);
}

std::vector<StepJunction> step_chain_junctions(const StepCurves& curves, const StepChain& chain,
                                               const ChainTolerances& tolerances) {
  return plugin().step_chain_junctions(curves, chain, tolerances);
}

}  // namespace cmr::import
