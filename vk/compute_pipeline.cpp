#include "vk/compute_pipeline.hpp"

#include "vk/internal.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <utility>

namespace cmr::vk {
namespace {

using detail::Buffer;
using detail::vk_error;

// A run that takes longer than this is treated as a hung device.
constexpr uint64_t kRunTimeoutNs = 120ull * 1000 * 1000 * 1000;
// Descriptor ranges must be non-zero, so an empty input binds this.
constexpr VkDeviceSize kEmptyStorageBytes = 16;
// Groups per row of the dispatch; more rows when the list needs more.
constexpr uint32_t kGroupsPerRow = 32768;

Error size_error(std::string message) { return Error{Errc::size_unsupported, VK_SUCCESS, std::move(message)}; }

}  // namespace

struct ComputePipeline::Impl : detail::PipelineCore {
  uint32_t push_constant_bytes = 0;
  std::vector<VkPipeline> follow_ups;  // the chain's further passes (run_chain), if made with any
  VkQueryPool timestamps = VK_NULL_HANDLE;  // 2 + follow-ups; none without compute timestamps
  uint32_t stamped = 0;                     // timestamps the last recorded run writes
  // Of the last finished run, read from the query pool only when asked
  // (last_pass_seconds): on lavapipe reading them took 24-43 us a run, a
  // tenth of a small frame's submission, which no frame but a profiled one
  // wants. Pending: a run has finished and its timestamps are not read yet.
  mutable std::vector<double> pass_seconds;
  mutable bool pass_seconds_pending = false;
  // A run starts: no pass times until it has finished.
  void forget_pass_seconds() {
    pass_seconds.clear();
    pass_seconds_pending = false;
  }

  Buffer input;     // device-local, read by the shader
  Buffer staging;   // host-visible source of the input upload
  Buffer output;    // device-local, written by the shader
  Buffer readback;  // host-visible destination of the output copy

  // What the descriptor set currently points at.
  VkBuffer bound_input = VK_NULL_HANDLE, bound_output = VK_NULL_HANDLE;
  VkDeviceSize bound_input_range = 0, bound_output_range = 0;

  Impl() = default;
  ~Impl();

  Result<void> create_pipeline(std::span<const uint32_t> spirv, std::span<const uint32_t> specialization,
                               std::span<const FollowUp> follow);
  Result<void> create_commands();
  // Grows `device_side` and its host-visible partner to at least `bytes`.
  Result<void> ensure(Buffer& device_side, Buffer& host_side, VkDeviceSize bytes, bool upload);
  Result<void> record(VkDeviceSize input_bytes, VkDeviceSize output_bytes, uint32_t count,
                      std::span<const std::byte> push_constants, const Chain* chain);
  Result<void> submit_and_wait(uint32_t count);
};

ComputePipeline::Impl::~Impl() {
  if (device == VK_NULL_HANDLE) return;
  wait_if_pending();
  for (Buffer* b : {&input, &staging, &output, &readback}) detail::destroy_buffer(device, *b);
  for (VkPipeline f : follow_ups) vkDestroyPipeline(device, f, nullptr);
  if (timestamps != VK_NULL_HANDLE) vkDestroyQueryPool(device, timestamps, nullptr);
}

Result<void> ComputePipeline::Impl::create_pipeline(std::span<const uint32_t> spirv,
                                                    std::span<const uint32_t> specialization,
                                                    std::span<const FollowUp> follow) {
  if (auto r = create_layouts_and_set(2, VK_SHADER_STAGE_COMPUTE_BIT, push_constant_bytes, "compute pipeline"); !r)
    return r.error();

  const detail::Specialization spec(specialization);
  const auto make = [&](std::span<const uint32_t> words, VkPipeline& out) -> Result<void> {
    detail::ShaderModule shader;
    if (auto r = shader.create(device, words, "compute shader"); !r) return r.error();
    VkComputePipelineCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
    info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = shader.handle;
    info.stage.pName = "main";
    info.stage.pSpecializationInfo = spec.info();
    info.layout = pipeline_layout;
    const VkResult r = vkCreateComputePipelines(device, state->pipeline_cache, 1, &info, nullptr, &out);
    if (r == VK_SUCCESS) return {};
    out = VK_NULL_HANDLE;
    Error e = vk_error(r, "vkCreateComputePipelines");
    // Anything but memory exhaustion here means the driver rejected the shader.
    if (e.code != Errc::out_of_memory && e.code != Errc::device_lost) {
      e.code = Errc::shader_invalid;
      e.message += "; the compute shader was rejected (check its interface: set 0 bindings 0 and 1, push constants)";
    }
    return e;
  };
  if (auto r = make(spirv, pipeline); !r) return r;
  for (const FollowUp& f : follow) {
    VkPipeline made = VK_NULL_HANDLE;
    if (auto r = make(f.spirv, made); !r) return r;
    follow_ups.push_back(made);
  }
  // Timestamps around each pass, where the device has them on compute
  // queues (a device without them still runs; it reports no pass times).
  if (state->limits.timestampComputeAndGraphics && state->limits.timestampPeriod > 0) {
    VkQueryPoolCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = static_cast<uint32_t>(2 + follow_ups.size());
    if (vkCreateQueryPool(device, &info, nullptr, &timestamps) != VK_SUCCESS) timestamps = VK_NULL_HANDLE;
  }
  return {};
}

Result<void> ComputePipeline::Impl::create_commands() {
  return detail::create_one_shot_commands(*this);
}

Result<void> ComputePipeline::Impl::ensure(Buffer& device_side, Buffer& host_side, VkDeviceSize bytes, bool upload) {
  if (device_side.buffer != VK_NULL_HANDLE && host_side.buffer != VK_NULL_HANDLE && device_side.size >= bytes)
    return {};
  // Grow geometrically so a slowly growing input does not reallocate every run.
  const VkDeviceSize capacity = std::max({bytes, 2 * device_side.size, VkDeviceSize{256}});
  detail::destroy_buffer(device, device_side);
  detail::destroy_buffer(device, host_side);
  bound_input = bound_output = VK_NULL_HANDLE;
  // The result is also written by the host's counters (run_chain) and read
  // as the follow-up's group counts.
  const VkBufferUsageFlags device_usage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
      (upload ? VK_BUFFER_USAGE_TRANSFER_DST_BIT
              : VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT);
  if (auto r = detail::create_buffer(*state, device_side, capacity, device_usage, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                                     upload ? "input buffer" : "result buffer");
      !r)
    return r;
  // Uploads prefer coherent memory; readbacks cached memory (fast host reads,
  // invalidated after the wait when not coherent).
  const auto r = upload ? detail::create_buffer(*state, host_side, capacity, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                                                VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, "staging buffer")
                        : detail::create_buffer(*state, host_side, capacity, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                                                VK_MEMORY_PROPERTY_HOST_CACHED_BIT, "readback buffer");
  if (!r) detail::destroy_buffer(device, device_side);  // keep the pair consistent for the next run
  return r;
}

Result<void> ComputePipeline::Impl::record(VkDeviceSize input_bytes, VkDeviceSize output_bytes, uint32_t count,
                                           std::span<const std::byte> push_constants, const Chain* chain) {
  // The previous run's fence has been waited on, so the pool is idle.
  if (VkResult r = vkResetCommandPool(device, command_pool, 0); r != VK_SUCCESS) return vk_error(r, "vkResetCommandPool");
  if (auto r = detail::begin_one_time(command_buffer); !r) return r.error();
  VkCommandBuffer cmd = command_buffer;

  stamped = 0;
  if (timestamps != VK_NULL_HANDLE) vkCmdResetQueryPool(cmd, timestamps, 0, static_cast<uint32_t>(2 + follow_ups.size()));
  const auto stamp = [&](VkPipelineStageFlagBits after) {
    if (timestamps != VK_NULL_HANDLE) vkCmdWriteTimestamp(cmd, after, timestamps, stamped++);
  };
  const VkBufferCopy in{0, 0, input_bytes};
  vkCmdCopyBuffer(cmd, staging.buffer, input.buffer, 1, &in);
  detail::buffer_barrier(cmd, input.buffer, 0, input_bytes, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  if (chain) {  // the queue's counters, before the first pass counts into them
    if (chain->zero_words > 0) vkCmdFillBuffer(cmd, output.buffer, 0, VkDeviceSize{chain->zero_words} * 4, 0);
    vkCmdUpdateBuffer(cmd, output.buffer, VkDeviceSize{chain->init_word} * 4, chain->init.size_bytes(),
                      chain->init.data());
    detail::buffer_barrier(cmd, output.buffer, 0, output_bytes, VK_ACCESS_TRANSFER_WRITE_BIT,
                           VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  }
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout, 0, 1, &descriptor_set, 0, nullptr);
  if (push_constant_bytes > 0)
    vkCmdPushConstants(cmd, pipeline_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes, push_constants.data());
  const uint32_t groups = (count + kGroupSize - 1) / kGroupSize;
  const uint32_t per_row = std::min(groups, kGroupsPerRow);
  stamp(VK_PIPELINE_STAGE_TRANSFER_BIT);  // the upload done
  if (count > 0) vkCmdDispatch(cmd, per_row, (groups + per_row - 1) / per_row, 1);
  stamp(VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  for (std::size_t i = 0; chain && i < follow_ups.size(); ++i) {  // each sized by what the passes before queued
    detail::buffer_barrier(cmd, output.buffer, 0, output_bytes, VK_ACCESS_SHADER_WRITE_BIT,
                           VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                           VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, follow_ups[i]);
    vkCmdDispatchIndirect(cmd, output.buffer, VkDeviceSize{chain->indirect_words[i]} * 4);
    stamp(VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  }
  detail::buffer_barrier(cmd, output.buffer, 0, output_bytes, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
  const VkBufferCopy out{0, 0, output_bytes};
  vkCmdCopyBuffer(cmd, output.buffer, readback.buffer, 1, &out);
  // Make the copied words visible to host reads after the fence wait.
  detail::buffer_barrier(cmd, readback.buffer, 0, output_bytes, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT);
  if (VkResult r = vkEndCommandBuffer(cmd); r != VK_SUCCESS) return vk_error(r, "vkEndCommandBuffer");
  return {};
}

Result<void> ComputePipeline::Impl::submit_and_wait(uint32_t count) {
  return detail::submit_and_wait(*this, kRunTimeoutNs,
                                 "computing " + std::to_string(count) +
                                     " items did not finish within 120 s; the device hangs or the shader is too slow");
}

Result<ComputePipeline> ComputePipeline::make(Context& context, std::span<const uint32_t> compute_spirv,
                                              uint32_t push_constant_bytes, std::span<const uint32_t> specialization,
                                              std::span<const FollowUp> follow_ups) {
  const std::shared_ptr<detail::DeviceState>& state = context.state();
  const uint32_t max_push = std::min(kMaxPushConstantBytes, state->limits.maxPushConstantsSize);
  if (push_constant_bytes % 4 != 0 || push_constant_bytes > max_push) {
    return size_error("push-constant block of " + std::to_string(push_constant_bytes) +
                      " bytes is not supported (a multiple of 4, at most " + std::to_string(max_push) + ")");
  }
  if (auto r = detail::check_spirv(compute_spirv, detail::ShaderStage::compute); !r) return r.error();
  for (const FollowUp& f : follow_ups)
    if (auto r = detail::check_spirv(f.spirv, detail::ShaderStage::compute); !r) return r.error();
  auto impl = std::make_unique<Impl>();
  impl->state = state;
  impl->device = state->device;
  impl->push_constant_bytes = push_constant_bytes;
  if (auto r = impl->create_pipeline(compute_spirv, specialization, follow_ups); !r) return r.error();
  if (auto r = impl->create_commands(); !r) return r.error();
  return ComputePipeline(std::move(impl));
}

Result<ComputePipeline> ComputePipeline::create(Context& context, std::span<const uint32_t> compute_spirv,
                                                uint32_t push_constant_bytes,
                                                std::span<const uint32_t> specialization) {
  return make(context, compute_spirv, push_constant_bytes, specialization, {});
}

Result<ComputePipeline> ComputePipeline::create(Context& context, std::span<const uint32_t> compute_spirv,
                                                std::span<const uint32_t> specialization,
                                                std::span<const FollowUp> follow_ups) {
  if (follow_ups.empty()) return size_error("a chain of passes needs at least one follow-up");
  return make(context, compute_spirv, 0, specialization, follow_ups);
}

Result<std::vector<uint32_t>> ComputePipeline::run(std::span<const std::byte> input, uint32_t count,
                                                   std::span<const std::byte> push_constants, uint32_t words) {
  std::vector<uint32_t> out(words == 0 ? count : words);
  auto r = run(input, count, push_constants, words, [&](std::span<const std::byte> bytes) {
    if (!out.empty()) std::memcpy(out.data(), bytes.data(), out.size() * 4);
  });
  if (!r) return r.error();
  return out;
}

Result<void> ComputePipeline::run(std::span<const std::byte> input, uint32_t count,
                                  std::span<const std::byte> push_constants, uint32_t words,
                                  const std::function<void(std::span<const std::byte>)>& read) {
  return run_passes(input, count, push_constants, words, read, nullptr);
}

Result<void> ComputePipeline::run_chain(std::span<const std::byte> input, uint32_t count, uint32_t words,
                                        const Chain& chain, const std::function<void(std::span<const std::byte>)>& read) {
  impl_->forget_pass_seconds();
  if (impl_->follow_ups.empty())
    return Error{Errc::other, VK_SUCCESS, "run_chain on a compute pipeline made without a follow-up pass"};
  if (chain.indirect_words.size() != impl_->follow_ups.size())
    return Error{Errc::other, VK_SUCCESS, "a chain names " + std::to_string(chain.indirect_words.size()) +
                                              " group counts for " + std::to_string(impl_->follow_ups.size()) +
                                              " follow-up passes"};
  bool outside = chain.init.empty() || chain.init.size() > 16384 ||
                 uint64_t{chain.init_word} + chain.init.size() > words || chain.zero_words > words;
  for (const uint32_t at : chain.indirect_words) outside = outside || uint64_t{at} + 3 > words;
  if (outside)
    return Error{Errc::other, VK_SUCCESS, "a chain's counters or group counts lie outside its " +
                                              std::to_string(words) + " result words"};
  return run_passes(input, count, {}, words, read, &chain);
}

Result<void> ComputePipeline::run_passes(std::span<const std::byte> input, uint32_t count,
                                         std::span<const std::byte> push_constants, uint32_t words,
                                         const std::function<void(std::span<const std::byte>)>& read,
                                         const Chain* chain) {
  Impl& p = *impl_;
  p.forget_pass_seconds();
  if (p.lost)
    return Error{Errc::device_lost, VK_ERROR_DEVICE_LOST, "an earlier run lost the device; create a new Context and pipeline"};
  if (!push_constants.empty() && push_constants.size() != p.push_constant_bytes) {
    return size_error("push constants are " + std::to_string(push_constants.size()) +
                      " bytes but the pipeline was created for " + std::to_string(p.push_constant_bytes));
  }
  const VkDeviceSize max_range = p.state->limits.maxStorageBufferRange;
  if (words == 0) words = count;
  const VkDeviceSize output_bytes = std::max<VkDeviceSize>(VkDeviceSize{words} * 4, kEmptyStorageBytes);
  if (input.size() > max_range || output_bytes > max_range) {
    return size_error("a storage buffer of " + std::to_string(std::max<VkDeviceSize>(input.size(), output_bytes)) +
                      " bytes exceeds device '" + p.state->info.name + "' limit of " + std::to_string(max_range) +
                      " bytes (maxStorageBufferRange)");
  }
  if (count == 0 && !chain) {
    const std::vector<std::byte> zeros(std::size_t{words} * 4);
    read(zeros);
    return {};
  }
  const uint64_t groups = (uint64_t{count} + kGroupSize - 1) / kGroupSize;
  if ((groups + kGroupsPerRow - 1) / kGroupsPerRow > p.state->limits.maxComputeWorkGroupCount[1])
    return size_error(std::to_string(count) + " items are more than one dispatch of device '" + p.state->info.name +
                      "' holds");

  const VkDeviceSize input_bytes = input.empty() ? kEmptyStorageBytes : input.size();
  if (auto r = p.ensure(p.input, p.staging, input_bytes, true); !r) return r.error();
  if (auto r = p.ensure(p.output, p.readback, output_bytes, false); !r) return r.error();
  if (input.empty()) {
    std::memset(p.staging.mapped, 0, static_cast<std::size_t>(input_bytes));
  } else {
    std::memcpy(p.staging.mapped, input.data(), input.size());
  }
  if (!p.staging.coherent) {
    const VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, p.staging.memory, 0, VK_WHOLE_SIZE};
    if (VkResult r = vkFlushMappedMemoryRanges(p.device, 1, &range); r != VK_SUCCESS)
      return vk_error(r, "vkFlushMappedMemoryRanges");
  }
  // Exact ranges, so that .length() of a runtime array in the shader sees the
  // caller's data, not the buffers' capacity.
  if (p.bound_input != p.input.buffer || p.bound_input_range != input_bytes || p.bound_output != p.output.buffer ||
      p.bound_output_range != output_bytes) {
    const std::array<VkDescriptorBufferInfo, 2> infos{VkDescriptorBufferInfo{p.input.buffer, 0, input_bytes},
                                                      VkDescriptorBufferInfo{p.output.buffer, 0, output_bytes}};
    detail::write_storage_set(p.device, p.descriptor_set, infos);
    p.bound_input = p.input.buffer;
    p.bound_input_range = input_bytes;
    p.bound_output = p.output.buffer;
    p.bound_output_range = output_bytes;
  }
  std::array<std::byte, kMaxPushConstantBytes> push{};  // zeros when none given
  std::copy(push_constants.begin(), push_constants.end(), push.begin());
  if (auto r = p.record(input_bytes, output_bytes, count, push, chain); !r) return r.error();
  if (auto r = p.submit_and_wait(count); !r) return r.error();
  if (!p.readback.coherent) {
    const VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, p.readback.memory, 0, VK_WHOLE_SIZE};
    if (VkResult r = vkInvalidateMappedMemoryRanges(p.device, 1, &range); r != VK_SUCCESS)
      return vk_error(r, "vkInvalidateMappedMemoryRanges");
  }
  p.pass_seconds_pending = true;
  read(std::span<const std::byte>(p.readback.mapped, std::size_t{words} * 4));
  return {};
}

const std::vector<double>& ComputePipeline::last_pass_seconds() const {
  const Impl& p = *impl_;
  if (!p.pass_seconds_pending) return p.pass_seconds;
  p.pass_seconds_pending = false;
  // The pool keeps the finished run's timestamps until the next run records.
  if (p.stamped >= 2) {
    std::vector<uint64_t> ticks(p.stamped);
    if (vkGetQueryPoolResults(p.device, p.timestamps, 0, p.stamped, ticks.size() * sizeof(uint64_t), ticks.data(),
                              sizeof(uint64_t), VK_QUERY_RESULT_64_BIT) == VK_SUCCESS)
      for (uint32_t k = 1; k < p.stamped; ++k)
        p.pass_seconds.push_back(static_cast<double>(ticks[k] - ticks[k - 1]) * p.state->limits.timestampPeriod * 1e-9);
  }
  return p.pass_seconds;
}

ComputePipeline::ComputePipeline(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ComputePipeline::ComputePipeline(ComputePipeline&&) noexcept = default;
ComputePipeline& ComputePipeline::operator=(ComputePipeline&&) noexcept = default;
ComputePipeline::~ComputePipeline() = default;

}  // namespace cmr::vk
