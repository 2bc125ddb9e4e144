#pragma once
/// The benchmark's baseline as its authors run it: the published method in
/// a shader (shaders/published_fp64.glsl), fp64, on the Vulkan device
/// (lavapipe here), every pixel shaded: one fragment per pixel as published,
/// or one compute invocation per pixel (on some GPUs the faster form). Same labels and errors as
/// cmr::bench::published_region (tools/bench/published_method.hpp).
#include <cstdint>
#include <vector>

#include "tools/bench/published_method.hpp"

namespace cmr::bench {

/// Labels of every pixel, row-major, row 0 at the top. Throws InputError as
/// published_region does, std::runtime_error when no Vulkan device with
/// fp64 is available or the device fails. One device and one pipeline per
/// (degree, depth, size, stage) for the whole process, built on first use.
enum class ShaderStage { fragment, compute };
std::vector<uint8_t> published_region_vulkan(const BSpline& spline, const PublishedRegion& request,
                                             ShaderStage stage = ShaderStage::fragment);

}  // namespace cmr::bench
