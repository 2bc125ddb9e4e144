// With the loader pointed at a driver file that does not exist there is no
// Vulkan device: every entry point must say so with Errc::no_device and one
// actionable line, not crash or pick something else.
#include "vk/context.hpp"

#include "vk/backend_choice.hpp"
#include "spline/fields.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
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
  // The library reads no environment (issue 41): the path is named by the
  // program that read it (BackendChoice::loader_selection, below).
  EXPECT_EQ(e.message.find(kMissingIcd), std::string::npos) << e.message;
}

TEST_F(NoDevice, ContextCreateReportsNoDevice) {
  auto context = Context::create({});
  ASSERT_FALSE(context) << "got device '" << context.value().device().name << "'";
  expect_no_device(context.error());
}

TEST_F(NoDevice, NamedDeviceAlsoReportsNoDevice) {
  ContextOptions options;
  options.device_name = "llvmpipe";
  auto context = Context::create(options);
  ASSERT_FALSE(context);
  expect_no_device(context.error());
}

TEST_F(NoDevice, EnumerateReportsNoDevice) {
  auto devices = enumerate_devices();
  ASSERT_FALSE(devices) << devices.value().size() << " device(s) listed";
  expect_no_device(devices.error());
}


// make_region_backend without a device: automatic falls back to the CPU
// backend and says so once through the note; vulkan throws the environment
// error itself (no caller re-wraps it), with what to do about it.
RegionProblem small_problem() {
  RegionRequest r;
  r.point = 1;
  r.width = r.height = 8;
  return RegionProblem::make(BSpline::bezier({{0, 0}, {1, 1}, {2, 0.2}}), r);
}

TEST_F(NoDevice, AutomaticBackendFallsBackToCpuAndAnnouncesIt) {
  std::vector<std::string> notes;
  // Measurements under which a device could win, so the loader is asked.
  BackendRates rates;
  rates.cpu_pixels_per_second = 1;
  rates.vulkan_pixels_per_second = 1e12;
  auto backend = make_region_backend({.kind = BackendKind::automatic, .rates = rates},
                                     [&](const std::string& n) { notes.push_back(n); });
  EXPECT_TRUE(notes.empty()) << "the choice is made at the first render or name()";
  const RegionResult r = backend->render(small_problem());
  EXPECT_EQ(backend->name(), "cpu");
  EXPECT_EQ(r.size(), 64u);
  ASSERT_EQ(notes.size(), 1u) << "announced exactly once";
  EXPECT_EQ(notes[0], kCpuFallbackNote);
  backend->render(small_problem());
  EXPECT_EQ(notes.size(), 1u);
}

// Where no device could win the job (the CPU unmeasured, or measured far
// faster), automatic does not ask the loader: the CPU renders, silently.
TEST_F(NoDevice, AutomaticAsksNoLoaderWhereNoDeviceCouldWin) {
  BackendRates fast_cpu;
  fast_cpu.cpu_pixels_per_second = 1e12;
  fast_cpu.vulkan_pixels_per_second = 1e6;
  for (const std::optional<BackendRates>& rates : {std::optional<BackendRates>{}, std::optional<BackendRates>{fast_cpu}}) {
    std::vector<std::string> notes;
    auto backend = make_region_backend({.kind = BackendKind::automatic, .rates = rates},
                                       [&](const std::string& n) { notes.push_back(n); });
    backend->render(small_problem());
    EXPECT_EQ(backend->name(), "cpu");
    EXPECT_TRUE(notes.empty()) << notes.front();
  }
}

TEST_F(NoDevice, CpuBackendIsNoFallback) {
  int notes = 0;
  auto backend = make_region_backend({.kind = BackendKind::cpu}, [&](const std::string&) { ++notes; });
  backend->render(small_problem());
  EXPECT_EQ(backend->name(), "cpu");
  EXPECT_EQ(notes, 0);
}

TEST_F(NoDevice, VulkanBackendThrowsEnvironmentErrorAtFirstRender) {
  auto backend = make_region_backend({.kind = BackendKind::vulkan,
                                      .precision = RegionPrecision::fp32,
                                      .loader_selection = std::string("VK_DRIVER_FILES='") + kMissingIcd + "'"});
  EXPECT_EQ(backend->name(), "vulkan");
  try {
    backend->render(small_problem());
    FAIL() << "rendered without a device";
  } catch (const EnvironmentError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no Vulkan device"), std::string::npos) << what;
    // Named by its field (spline/fields.hpp); the cmr command shows it as --backend cpu.
    EXPECT_NE(what.find("or use backend cpu"), std::string::npos) << what;
    EXPECT_NE(marked_text(e).find("or use " + field("backend") + " cpu"), std::string::npos) << what;
    // The stale path is named, since it is the likely cause.
    EXPECT_NE(what.find(std::string(kMissingIcd) + "'; check that the file exists"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
  }
}

// automatic's rule on device lists (the GPU branch cannot run on a machine
// without a GPU; the CPU branch runs above).
TEST(BackendAuto, TakesTheFirstDeviceThatIsNotACpu) {
  EXPECT_EQ(auto_backend_device({}), "") << "no device: the CPU backend";
  EXPECT_EQ(auto_backend_device({{"llvmpipe (LLVM 15.0.6, 256 bits)", true}}), "") << "lavapipe only: the CPU backend";
  EXPECT_EQ(auto_backend_device({{"llvmpipe (LLVM 15.0.6, 256 bits)", true}, {"NVIDIA H100 80GB HBM3", false}}),
            "NVIDIA H100 80GB HBM3")
      << "a GPU after lavapipe in loader order";
  EXPECT_EQ(auto_backend_device({{"AMD Radeon", false}, {"NVIDIA", false}}), "AMD Radeon");
}

}  // namespace
}  // namespace cmr::vk
