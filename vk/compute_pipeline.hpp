// Runs a compute shader once per item of a list and reads one 32-bit word
// per item back: one submission per run (upload, dispatch, copy out) and one
// fence wait, the whole list in a single dispatch.
//
// Shader interface the compute SPIR-V must follow:
//   layout(local_size_x = 64) in;  // ComputePipeline::kGroupSize, y = z = 1
//   layout(std430, set = 0, binding = 0) readonly buffer ... ;   // the input
//   layout(std430, set = 0, binding = 1) writeonly buffer ... { uint result[]; };
//   layout(push_constant) uniform ... ;  // exactly push_constant_bytes bytes
// Item `at` = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64 +
// gl_GlobalInvocationID.x (the dispatch is two-dimensional when the list
// needs more groups than one row may hold); the shader writes result[at] for
// every at < count (and, when run() asks for more words, those too) and
// nothing beyond, and must know `count` itself (from its input or push
// constants).
//
// A pipeline made with follow-ups (FollowUp) runs a chain of passes in the
// same submission: the first over `count` items, then each follow-up (a
// shader of the same interface and specialisation) with the group counts
// the passes before it wrote into the result (vkCmdDispatchIndirect): work
// queues on the device (the region shader's tile, pixel and double passes,
// shaders/region_layout.h). A follow-up's items are gl_GlobalInvocationID.x
// (one dimension).
//
// Why compute and not the fragment pipeline (vk/fragment_pipeline.hpp): no
// colour image, render pass or image-to-buffer copy, the list in one
// dispatch rather than a work area per submission, and on GPUs the compute
// stage is not bound by the graphics pipeline's per-fragment costs.
//
// Thread safety: as for Context (one thread at a time per Context).
#pragma once

#include "vk/context.hpp"
#include "vk/error.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace cmr::vk {

class ComputePipeline {
 public:
  static constexpr uint32_t kGroupSize = 64;
  static constexpr uint32_t kMaxPushConstantBytes = 128;

  // Builds the pipeline (through the device's pipeline cache) and its
  // command buffer and fence. specialization: value i for constant_id i.
  // Errors: size_unsupported (bad push_constant_bytes); shader_invalid (not
  //   a compute SPIR-V module, or rejected by the driver); out_of_memory;
  //   device_lost; other.
  static Result<ComputePipeline> create(Context& context, std::span<const uint32_t> compute_spirv,
                                        uint32_t push_constant_bytes = 0,
                                        std::span<const uint32_t> specialization = {});

  // A follow-up pass: its compute SPIR-V, specialised as the first pass.
  struct FollowUp {
    std::span<const uint32_t> spirv;
  };
  // The same, with follow-up passes (run_chain; at least one), no push
  // constants. Errors: as above.
  static Result<ComputePipeline> create(Context& context, std::span<const uint32_t> compute_spirv,
                                        std::span<const uint32_t> specialization,
                                        std::span<const FollowUp> follow_ups);

  ComputePipeline(ComputePipeline&&) noexcept;
  ComputePipeline& operator=(ComputePipeline&&) noexcept;
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;
  ~ComputePipeline();

  // Uploads `input` (bound at binding 0, range its exact size; empty binds 16
  // zero bytes), runs `count` items and returns the result buffer's `words`
  // words (0: one per item; more when each item writes several). Blocks
  // until done. Buffers grow geometrically and are kept between runs.
  // Errors: size_unsupported (input above maxStorageBufferRange, result
  //   above it, wrong push-constant size); out_of_memory; device_lost (also
  //   when a run does not finish within two minutes; every later run then
  //   fails with device_lost); other.
  Result<std::vector<uint32_t>> run(std::span<const std::byte> input, uint32_t count,
                                    std::span<const std::byte> push_constants = {}, uint32_t words = 0);
  // The same, but hands `read` the result's bytes (4 * words, or 4 * count
  // when words is 0) where the device left them, in host memory mapped for
  // this pipeline, valid during the call: the caller copies what it needs
  // straight to where it belongs.
  Result<void> run(std::span<const std::byte> input, uint32_t count, std::span<const std::byte> push_constants,
                   uint32_t words, const std::function<void(std::span<const std::byte>)>& read);

  // What a chain's submission does besides its passes: `init` is written to
  // result words init_word.. and the first zero_words words are set to 0
  // before the first pass (every other result word starts undefined), and
  // follow-up i's group
  // counts (x, y, z) are result words indirect_words[i]..+2 when the passes
  // before it end.
  struct Chain {
    uint32_t init_word = 0;
    std::span<const uint32_t> init;
    std::span<const uint32_t> indirect_words;  ///< one per follow-up
    uint32_t zero_words = 0;                   ///< result words 0.. set to 0 before the first pass
  };
  // run() for a pipeline made with follow-ups: every pass in one
  // submission, then one copy of the `words` result words to `read`.
  // Errors: as run(); other when the pipeline has no follow-up, the chain
  //   names another number of them, or `init` or the group counts lie
  //   outside `words`.
  Result<void> run_chain(std::span<const std::byte> input, uint32_t count, uint32_t words, const Chain& chain,
                         const std::function<void(std::span<const std::byte>)>& read);

  // The device's time for each pass of the last run or chain, in seconds
  // (timestamps after the upload and after each dispatch), read from the
  // device on the first call after a run; empty when the device has no
  // compute timestamps (timestampComputeAndGraphics) or the last run did
  // not finish (it failed, or had nothing to dispatch).
  const std::vector<double>& last_pass_seconds() const;

 private:
  // Both create()s: the checks, the pipelines, the commands.
  static Result<ComputePipeline> make(Context& context, std::span<const uint32_t> compute_spirv,
                                      uint32_t push_constant_bytes, std::span<const uint32_t> specialization,
                                      std::span<const FollowUp> follow_ups);
  Result<void> run_passes(std::span<const std::byte> input, uint32_t count, std::span<const std::byte> push_constants,
                          uint32_t words, const std::function<void(std::span<const std::byte>)>& read,
                          const Chain* chain);
  struct Impl;
  explicit ComputePipeline(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmr::vk
