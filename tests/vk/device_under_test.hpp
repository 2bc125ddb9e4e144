#pragma once
// The Vulkan device these tests run on: the one Context::create({}) picks
// from the driver that VK_DRIVER_FILES names. CTest sets it from the cache
// variable CMR_TEST_VK_DRIVER_FILES (lavapipe by default, a GPU's driver when
// configured so), and the tests name this device rather than "llvmpipe", so
// that they run unchanged on a GPU.
#include <string>

#include "vk/context.hpp"

namespace cmr::vk::test {

/// The default device's name, asked once per program; empty when there is
/// none (the caller's Context::create then fails with the reason).
inline const std::string& device_under_test() {
  static const std::string name = [] {
    auto context = Context::create({});
    return context ? context.value().device().name : std::string{};
  }();
  return name;
}

/// True when VK_DRIVER_FILES selects Mesa lavapipe (the default under CTest).
inline bool is_lavapipe(const std::string& device_name) {
  return device_name.find("llvmpipe") != std::string::npos;
}

}  // namespace cmr::vk::test
