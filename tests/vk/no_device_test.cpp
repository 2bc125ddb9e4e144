// With the loader pointed at a driver file that does not exist there is no
// Vulkan device: every entry point must say so with Errc::no_device and one
// actionable line, not crash or pick something else.
#include "vk/context.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace cmr::vk {
namespace {

constexpr const char* kMissingIcd = "/nonexistent/cmr-no-such-driver.json";

// CTest already sets VK_DRIVER_FILES for this executable; setting it here too
// keeps the test meaningful when the binary is run by hand. The loader reads
// the environment on every vkCreateInstance, so this must run before it.
class NoDevice : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(setenv("VK_DRIVER_FILES", kMissingIcd, 1), 0);
    unsetenv("VK_ICD_FILENAMES");
    unsetenv("VK_ADD_DRIVER_FILES");
  }
};

void expect_no_device(const Error& e) {
  EXPECT_EQ(e.code, Errc::no_device) << to_string(e.code) << ": " << e.message;
  EXPECT_EQ(e.message.find('\n'), std::string::npos) << "message must be one line: " << e.message;
  EXPECT_NE(e.message.find("no Vulkan device"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("mesa-vulkan-drivers"), std::string::npos) << e.message;
  // The stale path is named, since it is the likely cause.
  EXPECT_NE(e.message.find(kMissingIcd), std::string::npos) << e.message;
}

TEST_F(NoDevice, ContextCreateReportsNoDevice) {
  auto context = Context::create({});
  ASSERT_FALSE(context) << "got device '" << context.value().device().name << "'";
  expect_no_device(context.error());
}

TEST_F(NoDevice, NamedDeviceAlsoReportsNoDevice) {
  auto context = Context::create({.device_name = "llvmpipe"});
  ASSERT_FALSE(context);
  expect_no_device(context.error());
}

TEST_F(NoDevice, EnumerateReportsNoDevice) {
  auto devices = enumerate_devices();
  ASSERT_FALSE(devices) << devices.value().size() << " device(s) listed";
  expect_no_device(devices.error());
}

}  // namespace
}  // namespace cmr::vk
