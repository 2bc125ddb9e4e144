// Runs a fragment shader once per pixel of an offscreen R32_UINT image and
// reads the result back: a "compute via rasterisation" helper.
//
// Shader interface the fragment SPIR-V must follow:
//   layout(std430, set = 0, binding = 0) readonly buffer ... ;  // optional
//   layout(push_constant) uniform ... ;  // exactly push_constant_bytes bytes
//   layout(location = 0) out uint result;
// gl_FragCoord.xy is the pixel centre (x + 0.5, y + 0.5); y = 0 is row 0 of
// the result, the top row of the image.
//
// Thread safety: as for Context (one thread at a time per Context).
#pragma once

#include "vk/context.hpp"
#include "vk/error.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace cmr::vk {

class FragmentPipeline {
 public:
  // Rows rendered per submission. Each band is its own submit + fence wait,
  // which keeps a single submission short enough for the display watchdog
  // of desktop GPUs (typically ~2 s) even with expensive shaders.
  static constexpr uint32_t kDefaultBandRows = 256;
  static constexpr uint32_t kMaxPushConstantBytes = 128;

  // Builds the pipeline and allocates everything run() needs (image,
  // readback buffer, command buffer, fence). The built-in vertex shader
  // draws one full-screen triangle. The Context may be destroyed before the
  // pipeline (the device is shared).
  //
  // fragment_spirv: SPIR-V words (e.g. from a cmr_add_shader() header).
  // push_constant_bytes: size of the shader's push-constant block, a
  //   multiple of 4, at most 128; 0 if it has none.
  // band_rows: rows per submission, >= 1 (clamped to height).
  // specialization: 32-bit values of the fragment shader's specialization
  //   constants, value i for constant_id i (array sizes such as the degree).
  //
  // Errors: size_unsupported (width/height 0 or above the device's 2D image
  //   limit, bad push_constant_bytes, band_rows 0); shader_invalid (not
  //   SPIR-V, or rejected by the driver); missing_feature (R32_UINT colour
  //   attachments unsupported); out_of_memory; device_lost; other.
  static Result<FragmentPipeline> create(Context& context, std::span<const uint32_t> fragment_spirv,
                                         uint32_t width, uint32_t height,
                                         uint32_t push_constant_bytes = 0,
                                         uint32_t band_rows = kDefaultBandRows,
                                         std::span<const uint32_t> specialization = {});

  FragmentPipeline(FragmentPipeline&&) noexcept;
  FragmentPipeline& operator=(FragmentPipeline&&) noexcept;
  FragmentPipeline(const FragmentPipeline&) = delete;
  FragmentPipeline& operator=(const FragmentPipeline&) = delete;
  ~FragmentPipeline();

  // Renders the whole image and returns it row-major, width * height values,
  // index y * width + x, row 0 = top (gl_FragCoord.y = 0.5). Blocks until
  // done. May be called any number of times; buffers are reused and only
  // the storage buffer is reallocated, when a larger one is passed.
  //
  // storage_buffer: bytes bound at set 0 binding 0, range = its exact size
  //   (so .length() of a runtime array sees exactly this data). Empty binds
  //   16 zero bytes.
  // push_constants: empty (zeros are pushed) or exactly push_constant_bytes.
  //
  // Errors: size_unsupported (storage buffer above maxStorageBufferRange,
  //   wrong push-constant size); out_of_memory; device_lost (also when a
  //   band does not finish within two minutes; the pipeline is then
  //   unusable and every later run() fails with device_lost); other.
  // areas: when not empty, only these pixel rectangles run the shader (one
  //   scissored draw each); every other pixel reads 0, the clear value.
  Result<std::vector<uint32_t>> run(std::span<const std::byte> storage_buffer,
                                    std::span<const std::byte> push_constants = {},
                                    std::span<const VkRect2D> areas = {});

  uint32_t width() const;
  uint32_t height() const;
  uint32_t band_rows() const;

 private:
  struct Impl;
  explicit FragmentPipeline(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmr::vk
