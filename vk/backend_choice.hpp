#pragma once
// Which region backend renders: the one choice behind `cmr --backend
// auto|vulkan|cpu --precision --device` (and any program that renders
// regions). A library decision, announced when it falls back:
//  - cpu: CpuRegionBackend.
//  - vulkan: the Vulkan device `device` names (else the first suitable),
//    opened at the first render (a run that renders nothing opens none);
//    when it is missing or fails, render throws EnvironmentError
//    (spline/errors.hpp) with a line that says how to select lavapipe, or to
//    use the CPU backend.
//  - automatic: Vulkan when the loader lists a real GPU (a device whose type
//    is not VK_PHYSICAL_DEVICE_TYPE_CPU, i.e. not lavapipe/llvmpipe) or when
//    `device` names one; else the CPU backend, which is faster than a
//    software rasterizer, and the note (if given) is called once with a line
//    that says so. Decided at the first render or name(), whichever comes
//    first; name() then says the choice ("vulkan" or "cpu"), so callers
//    report the backend that actually ran.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bezierize/region.hpp"
#include "vk/region_vk.hpp"

namespace cmr::vk {

enum class BackendKind { cpu, vulkan, automatic };

/// What make_region_backend builds.
struct BackendChoice {
  BackendKind kind = BackendKind::automatic;          ///< see the header comment
  RegionPrecision precision = RegionPrecision::fp64;  ///< Vulkan's shader arithmetic; labels are certified either way
  std::string device;  ///< Vulkan device name (case-insensitive substring); empty: the first suitable (vulkan), the first GPU (automatic)
};

/// A device as the loader lists it, for auto_backend_device.
struct ListedDevice {
  std::string name;
  bool cpu = false;  ///< VK_PHYSICAL_DEVICE_TYPE_CPU (lavapipe/llvmpipe)
};
/// BackendKind::automatic's rule on the devices the loader lists (in loader
/// order): the name of the first one that is not a CPU device, which
/// automatic opens; "" when there is none, and automatic takes the CPU
/// backend.
std::string auto_backend_device(const std::vector<ListedDevice>& devices);

/// Receives the one-line note of a fallback (the cmr command prints it on
/// stderr as "note: ...").
using BackendNote = std::function<void(const std::string&)>;

/// The backend of `choice` (see the header comment). `note` is called at
/// most once, when BackendKind::automatic falls back to the CPU backend.
std::shared_ptr<RegionBackend> make_region_backend(const BackendChoice& choice, BackendNote note = {});

/// The text of automatic's fallback note.
inline constexpr const char* kCpuFallbackNote =
    "no GPU found, so the CPU backend renders (--backend vulkan uses a CPU Vulkan device such as lavapipe)";

}  // namespace cmr::vk
