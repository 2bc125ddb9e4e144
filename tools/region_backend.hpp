#pragma once
// Chooses and runs a region backend for the CLI commands (region, figures,
// report). The Vulkan backend runs on the device the options name (lavapipe
// on a machine without a GPU); the CPU backend uses every core.
#include <string>

#include "bezierize/region.hpp"

namespace cmr::cli {

enum class Backend { vulkan, cpu };
enum class Precision { fp64, fp32 };

struct BackendOptions {
  Backend backend = Backend::vulkan;
  Precision precision = Precision::fp64;
  std::string device;  ///< Vulkan device name (substring); empty: the first suitable
  int threads = 0;     ///< CPU threads (CPU backend, and the Vulkan backend's host part); 0: all cores
  bool cull = true;    ///< Vulkan: let the host decide whole blocks first (off: the device shades every pixel)
};

/// Renders the region of `setup` on the chosen backend. Labels are identical
/// across backends and precisions: every pixel is certified or recomputed
/// exactly. Throws EnvironmentError (exit 3) when the Vulkan device is
/// missing or fails, with a line that says how to select lavapipe.
RegionImage render_region(const RegionSetup& setup, const BackendOptions& options);

/// Seconds spent creating the Vulkan context and pipeline (shader compile
/// included) in the last render_region call that created them; 0 if reused.
double last_setup_seconds();

}  // namespace cmr::cli
