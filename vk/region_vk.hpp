#pragma once
// The Vulkan region backend. On a CPU device (lavapipe) the host decides
// whole blocks of pixels where the certified path holds over them (most of a
// typical image) and the device classifies the pixels of the blocks left
// undecided; on a GPU the device classifies every pixel (DeviceShare). Either
// way one compute invocation takes a pixel, in one dispatch
// (vk/compute_pipeline.hpp; the shader shaders/region_common.glsl, buffer
// layout in shaders/region_layout.h), and the device flags what it cannot
// certify, which the host then decides (certified, then exactly). So labels
// equal CpuRegionBackend's, fp64 and fp32 alike.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "region/region.hpp"
#include "spline/fields.hpp"
#include "vk/context.hpp"
#include "vk/compute_pipeline.hpp"

namespace cmr::backend {
struct RegionImage;
}

namespace cmr::vk {

enum class RegionPrecision { fp64, fp32 };

/// A fault a test makes the backend report, as the driver would: at the
/// first render, device_lost after the frame's submission, out_of_memory at
/// the frame's buffers, pipeline_rejected when the pipeline is created
/// (shader_invalid, as the H200 rejected a degree-7 rational space pipeline).
/// Only tests and tools/ set it (`cmr` reads CMR_VK_FAULT, tools/cli_common.cpp).
enum class InjectedFault { none, device_lost, out_of_memory, pipeline_rejected };

/// How the work of a frame is shared between the host and the device:
/// - culled: the host proves whole blocks first (on all its threads) and the
///   device classifies the pixels left, down to the precomputed pieces;
///   deeper pieces and uncertain signs go back to the host.
/// - whole: the device does the whole frame in one submission: a tile pass
///   proves tiles of 8 x 8 pixels over their boxes (the block proofs' rule,
///   shaders/region_tiles.glsl) and queues the others, then a pixel pass
///   classifies the queued tiles' pixels, halving pieces below the
///   precomputed levels itself (load_deep); it returns the label (and
///   depth) map as bytes and a list of the pixels it flags uncertain, which
///   alone the host decides.
/// - automatic: culled on a CPU device (lavapipe: its lanes are the host's
///   cores, and deep halving in per-lane arrays costs more there than the
///   host's own traversal), whole on a GPU (the host's block proofs and its
///   deep pixels had bounded the frame there: docs/performance.md).
enum class DeviceShare { automatic, culled, whole };

/// How a VulkanRegionBackend is created.
struct VulkanRegionOptions {
  std::string device;                                 ///< device name (case-insensitive substring); empty: the first suitable
  RegionPrecision precision = RegionPrecision::fp64;  ///< shader arithmetic; labels are certified either way
  DeviceShare share = DeviceShare::automatic;         ///< see DeviceShare
  /// The whole share as a cascade: its tile and pixel passes in fp32, then
  /// an fp64 pass over the pixels they could not certify, in the same
  /// submission (for GPUs whose fp64 is slow); `precision` is then unused.
  /// On a device without shaderFloat64, fp32 alone; on the culled share, fp64.
  bool cascade = false;
  int threads = 0;                                    ///< host threads (culling, uncertain pixels); 0: all cores
  /// Most pixels one run takes (0: as the 2^27-byte storage buffers every
  /// device allows hold; the whole share rounds down to whole tile rows, at
  /// least one; tests set fewer to cover the split frame).
  std::size_t pixels_per_run = 0;
  /// Most pixels the device flags for the host that a run of the whole
  /// share lists (0: 2^16; beyond them the host finds the flagged pixels in
  /// the label map; tests set fewer to cover that).
  std::size_t flagged_per_run = 0;
  /// Where the VkPipelineCache is kept across runs (the file
  /// vulkan-pipelines-VENDOR-DEVICE.bin, rewritten whenever a pipeline is
  /// created); empty: pipelines are cached only for the backend's lifetime.
  std::string cache_dir;
  InjectedFault fault = InjectedFault::none;  ///< tests only (see InjectedFault)
  /// Tests only: the shader's polynomial error bound divided by 2^bits (a
  /// bound too small on purpose: the certification tests must then fail).
  int weaken_bound_bits = 0;
};

/// A Vulkan failure during a render (device lost, out of memory), carrying
/// the vk::Error: thrown by VulkanRegionBackend::render. A BackendError, so
/// an EnvironmentError (spline/errors.hpp): callers need not re-wrap it.
class RegionFailure : public BackendError, public FieldMessage {
 public:
  explicit RegionFailure(Error e)
      : BackendError(plain_fields(e.message)), FieldMessage(e.message), error_(std::move(e)) {}
  const Error& error() const { return error_; }

 private:
  Error error_;
};

/// Owns its Context and its pipelines, cached by the shader's specialisation
/// constants (degree, depth, precision, mode, varying joints), so repeated
/// renders (every point of a spline, interactive use) compile once.
class VulkanRegionBackend final : public RegionBackend {
 public:
  /// Opens the device. Errors: as Context::create (no_device,
  /// device_not_found, loader_missing, ...). fp64 is checked per render, so
  /// fp32 works on any device.
  static Result<VulkanRegionBackend> create(const VulkanRegionOptions& options = {});

  /// The render, or the Vulkan error: as ComputePipeline::create / run;
  /// missing_feature when fp64 is asked of a device without shaderFloat64.
  Result<RegionResult> try_render(const RegionProblem& problem);
  /// try_render's result; throws InputError for size_unsupported (the
  /// request exceeds a device limit), RegionFailure for any other error.
  RegionResult render(const RegionProblem& problem) override;
  std::string name() const override { return "vulkan"; }

  const DeviceInfo& device() const { return context_.device(); }
  const VulkanRegionOptions& options() const { return options_; }
  /// Seconds spent creating pipelines (shader compilation) so far.
  double pipeline_seconds() const { return pipeline_seconds_; }
  /// Seconds create() took (instance, device, pipeline cache file).
  double open_seconds() const { return open_seconds_; }
  /// Why the pipeline cache file was not used (a damaged or foreign file):
  /// one line, else empty. One that cannot be written is not noted.
  const std::string& cache_note() const { return cache_note_; }
  /// The pipeline cache file (empty without options().cache_dir).
  std::string cache_file() const;
  /// The share of the work this backend's frames run with (DeviceShare:
  /// automatic resolved by the device's type).
  DeviceShare share() const;

  /// What the device did in the last frame of the whole share.
  struct WholeFrame {
    std::size_t tiles = 0;         ///< tiles of TILE x TILE pixels (shaders/region_layout.h)
    std::size_t tiles_queued = 0;  ///< tiles the tile pass did not prove, left to the pixel pass
    std::size_t flagged = 0;       ///< pixels the device left to the host
    std::size_t second = 0;        ///< cascade: pixels the fp32 passes left to the fp64 pass
    /// The device's seconds in the tile pass, the pixel pass and (a
    /// cascade) the fp64 pass, over the frame's runs; empty on a device
    /// without compute timestamps.
    std::vector<double> pass_seconds;
  };
  const WholeFrame& last_whole_frame() const { return frame_; }

 private:
  struct Key {
    int degree, depth;
    RegionPrecision precision;
    bool cmr, joints;
    bool rational;
    bool deep;  ///< the device halves pieces below the precomputed levels (DeviceShare::whole)
    bool cascade;  ///< whole share: fp32 passes, then fp64 (VulkanRegionOptions::cascade)
    bool operator==(const Key&) const = default;
  };
  VulkanRegionBackend(Context context, VulkanRegionOptions options)
      : context_(std::move(context)), options_(std::move(options)) {}
  Result<ComputePipeline*> pipeline_for(const cmr::backend::RegionSetup& setup, bool deep);
  /// Whether a whole-share frame runs as a cascade (options and device).
  bool cascade() const;
  /// The culled share: one result word per listed pixel, in order
  /// (shaders/region_layout.h), into `words`.
  Result<void> shade_listed(const cmr::backend::RegionSetup& setup, const std::vector<std::array<int, 2>>& pixels,
                            std::vector<uint32_t>& words);
  /// The whole share: the label (and depth) map into `image`.
  Result<void> shade_whole(const cmr::backend::RegionSetup& setup, cmr::backend::RegionImage& image);
  /// What both shares check before they reach the device.
  Result<ComputePipeline*> prepare(const cmr::backend::RegionSetup& setup, bool deep);

  void save_pipeline_cache();

  Context context_;
  VulkanRegionOptions options_;
  std::vector<std::pair<Key, ComputePipeline>> pipelines_;
  double pipeline_seconds_ = 0;
  double open_seconds_ = 0;
  std::string cache_note_;
  WholeFrame frame_;
};

}  // namespace cmr::vk
