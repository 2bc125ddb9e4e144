#pragma once
// Which region backend renders: the one choice behind `cmr --backend
// auto|vulkan|cpu --precision --device` (and any program that renders
// regions). A library decision, announced when it falls back:
//  - cpu: CpuRegionBackend.
//  - vulkan: the Vulkan device `device` names (else the first suitable),
//    opened at the first render (a run that renders nothing opens none);
//    when it is missing or cannot be opened, render throws EnvironmentError
//    (spline/errors.hpp) with a line that says how to select lavapipe, or to
//    use the CPU backend. A failure after it opened (device lost, out of
//    device memory, a pipeline the driver rejects) is announced in one note
//    and that frame and every later one render on the CPU backend (the same
//    labels). A device without shaderFloat64 asked for fp64 still throws
//    (RegionFailure: use --precision fp32), and a size over a device limit
//    InputError.
//  - automatic: per frame, the backend auto_rule picks from measured speeds
//    (BackendRates, kept in the cache directory) for the frames still to
//    come; a Vulkan device is a candidate only when the loader lists a real
//    GPU (type not VK_PHYSICAL_DEVICE_TYPE_CPU, so not lavapipe) or `device`
//    names one. The loader is asked (an instance: tens of milliseconds)
//    only once the rule could pick some device for the frame: an unmeasured
//    one for exploration, or one the rates file holds; until then the CPU
//    renders without a note (its frames measure r_cpu). Asked and no
//    candidate: the CPU backend, with kCpuFallbackNote once.
//    name() says the backend of the last frame (before any frame, the one
//    the rule would pick for one frame of 512x512), so callers report what
//    actually ran.
//
// The rule (docs/region.md, "Which backend auto picks"): with p pixels a
// frame, n frames to come, measured rates r_cpu and r_vk (pixels per second
// of a frame, Vulkan with its pipeline made) and Vulkan's fixed cost F
// (device start + pipeline creation through the pipeline cache, 0 once
// paid), estimate
//     T_cpu = n p / r_cpu,        T_vk = F + n p / r_vk
// and pick Vulkan only when T_vk < T_cpu. Unmeasured r_cpu: the CPU (it
// measures itself at no fixed cost). Unmeasured Vulkan: the CPU, unless the
// job is long enough that one exploratory Vulkan frame costs at most a
// quarter of T_cpu at the pessimistic priors (F = kPriorVulkanFixedSeconds,
// r_vk = r_cpu / kPriorVulkanSlowdown); the rule then decides again with
// that frame's measurement. So a one-shot frame goes to the CPU unless
// Vulkan was measured faster for it, start-up included.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "region/region.hpp"
#include "region/space_region.hpp"
#include "spline/fields.hpp"
#include "vk/region_vk.hpp"

namespace cmr::vk {

enum class BackendKind { cpu, vulkan, automatic };

/// Measured speeds, automatic's evidence (0: not measured).
struct BackendRates {
  double cpu_pixels_per_second = 0;     ///< a frame on the CPU backend, this machine's cores
  double vulkan_pixels_per_second = 0;  ///< a frame on the Vulkan device, its pipeline made
  double vulkan_open_seconds = 0;       ///< VulkanRegionBackend::create (instance, device, cache file)
  double vulkan_compile_seconds = 0;    ///< one pipeline, through the pipeline cache as it was
};

/// The work automatic decides for.
struct RegionJob {
  double pixels = 0;         ///< per frame
  int frames = 1;            ///< frames still to render, this one included (>= 1)
  bool vulkan_open = false;  ///< device started and a pipeline made already (F is paid)
};

/// auto_rule's answer with its estimates (seconds; 0 where unknown).
struct AutoDecision {
  BackendKind kind = BackendKind::cpu;  ///< cpu or vulkan
  double cpu_seconds = 0, vulkan_seconds = 0;
  bool explore = false;  ///< Vulkan picked to measure it (no Vulkan rate yet)
};

inline constexpr double kPriorVulkanFixedSeconds = 0.5;  ///< F before Vulkan was measured
inline constexpr double kPriorVulkanSlowdown = 4;        ///< r_vk = r_cpu / this before it was measured
inline constexpr double kExploreShare = 0.25;            ///< an exploratory frame's cost, at most this share of T_cpu
inline constexpr int kManyFrames = 64;                   ///< BackendChoice::frames = 0 (a report's thumbnails)

/// The rule of the header comment.
AutoDecision auto_rule(const BackendRates& rates, const RegionJob& job);

/// The rates kept in `cache_dir`/backend-rates.txt for this machine's CPU
/// backend (keyed by its core count) and the Vulkan device `device` (keyed
/// by its name); zeros for what it does not hold or when the file is missing
/// or damaged (a line that does not parse is skipped).
BackendRates load_backend_rates(const std::string& cache_dir, const std::string& device);
/// Writes `rates` for `device` (and the CPU) into the same file, keeping the
/// other devices' lines; written beside and renamed over. False when it
/// cannot be written (the rates then live only in this process).
bool store_backend_rates(const std::string& cache_dir, const std::string& device, const BackendRates& rates);

/// What make_region_backend builds.
struct BackendChoice {
  BackendKind kind = BackendKind::automatic;          ///< see the header comment
  RegionPrecision precision = RegionPrecision::fp64;  ///< Vulkan's shader arithmetic; labels are certified either way
  std::string device{};  ///< Vulkan device name (case-insensitive substring); empty: the first suitable (vulkan), the first GPU (automatic)
  int frames = 1;      ///< frames the job will render (cmr region: its points; sweep: its steps); 0: many, not known
  std::string cache_dir{};  ///< the pipeline cache and backend-rates.txt live here; empty: nothing kept across runs
  InjectedFault fault = InjectedFault::none;  ///< tests only: a Vulkan failure to report (vk/region_vk.hpp)
  /// The loader's driver selection as the program read it (e.g.
  /// "VK_DRIVER_FILES='/path.json'"); named in the line of a missing device,
  /// since a stale path is the usual cause. The library reads no environment.
  std::string loader_selection{};
  std::optional<BackendRates> rates{};        ///< tests only: automatic's evidence instead of the cache's
};

/// A device as the loader lists it, for auto_backend_device.
struct ListedDevice {
  std::string name;
  bool cpu = false;  ///< VK_PHYSICAL_DEVICE_TYPE_CPU (lavapipe/llvmpipe)
};
/// BackendKind::automatic's candidate among the devices the loader lists (in
/// loader order): the first whose name contains `wanted` (case-insensitive)
/// when it is not empty, else the first that is not a CPU device; "" when
/// there is none, and automatic takes the CPU backend.
std::string auto_backend_device(const std::vector<ListedDevice>& devices, const std::string& wanted = "");

/// Receives the one-line notes of fallbacks (the cmr command prints them on
/// stderr as "note: ..."). A note may name option fields, marked
/// (spline/fields.hpp): plain_fields gives their names.
using BackendNote = std::function<void(const std::string&)>;

/// The backend of `choice` (see the header comment). `note` is called once
/// per fallback: automatic without a candidate device, a Vulkan failure
/// after the device opened, a pipeline cache file that is not used.
std::shared_ptr<RegionBackend> make_region_backend(const BackendChoice& choice, BackendNote note = {});

/// The space-region backend of `choice` (region/space_region.hpp): cpu
/// and automatic render on the CPU (automatic has no measured rule for space
/// curves: their device runs are not timed yet), vulkan on the device
/// `device` names (VulkanSpaceRegionBackend, vk/space_region_vk.hpp).
std::shared_ptr<SpaceRegionBackend> make_space_region_backend(const BackendChoice& choice);

/// The text of automatic's fallback note (naming the field backend).
inline const std::string kCpuFallbackNote = "no GPU found, so the CPU backend renders (" + field("backend") +
                                            " vulkan uses a CPU Vulkan device such as lavapipe)";

}  // namespace cmr::vk
