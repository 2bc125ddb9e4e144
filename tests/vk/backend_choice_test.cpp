// `--backend auto`'s rule (vk/backend_choice.hpp, docs/region.md "Which
// backend auto picks"): unit tests with injected measurements, the rates
// file, and on the test device (lavapipe) the rule's decision for a one-shot
// 512x512 frame checked against that frame's measured cost on both backends.
// Also the Vulkan fallbacks (device lost, out of memory, a rejected pipeline,
// a damaged pipeline cache): one note, the CPU backend's labels, and through
// `cmr` exit 0 with one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "spline/spline_json.hpp"
#include "tests/cli_util.hpp"
#include "vk/backend_choice.hpp"
#include "device_under_test.hpp"

namespace cmr::vk {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kFrame = 512.0 * 512.0;

BackendRates rates(double cpu, double vk, double open, double compile) {
  BackendRates r;
  r.cpu_pixels_per_second = cpu;
  r.vulkan_pixels_per_second = vk;
  r.vulkan_open_seconds = open;
  r.vulkan_compile_seconds = compile;
  return r;
}

RegionJob job(double pixels, int frames, bool open = false) {
  RegionJob j;
  j.pixels = pixels;
  j.frames = frames;
  j.vulkan_open = open;
  return j;
}

TEST(AutoRule, UnmeasuredCpuRendersOnTheCpu) {
  EXPECT_EQ(auto_rule(rates(0, 1e12, 0, 0), job(kFrame, 1000)).kind, BackendKind::cpu);
}

TEST(AutoRule, OneShotPaysTheDeviceStart) {
  // Vulkan 10x faster per pixel, but 0.1 s to start: a 512^2 frame at
  // 100 Mp/s on the CPU takes 2.6 ms.
  const AutoDecision d = auto_rule(rates(100e6, 1e9, 0.08, 0.02), job(kFrame, 1));
  EXPECT_EQ(d.kind, BackendKind::cpu);
  EXPECT_NEAR(d.cpu_seconds, kFrame / 100e6, 1e-12);
  EXPECT_NEAR(d.vulkan_seconds, 0.1 + kFrame / 1e9, 1e-12);
}

TEST(AutoRule, ASweepAmortisesTheDeviceStart) {
  EXPECT_EQ(auto_rule(rates(100e6, 1e9, 0.08, 0.02), job(1024.0 * 1024.0, 1000)).kind, BackendKind::vulkan);
  // ... unless the device is slower per pixel, however many frames.
  EXPECT_EQ(auto_rule(rates(100e6, 90e6, 0, 0), job(kFrame, 1000000)).kind, BackendKind::cpu);
  // Once open, the fixed cost is paid: a single frame goes where it is faster.
  EXPECT_EQ(auto_rule(rates(100e6, 1e9, 10, 10), job(kFrame, 1, true)).kind, BackendKind::vulkan);
}

TEST(AutoRule, UnmeasuredDeviceIsExploredOnlyWhenTheJobIsLong) {
  // r_cpu 10 Mp/s, 64 frames of 1 Mp: T_cpu = 6.7 s; one frame at the priors
  // costs 0.5 + 4 * 0.1 s = 0.9 s <= 25%.
  const AutoDecision d = auto_rule(rates(10e6, 0, 0, 0), job(1 << 20, 64));
  EXPECT_EQ(d.kind, BackendKind::vulkan);
  EXPECT_TRUE(d.explore);
  EXPECT_EQ(auto_rule(rates(10e6, 0, 0, 0), job(1 << 20, 1)).kind, BackendKind::cpu);
  EXPECT_EQ(auto_rule(rates(10e6, 0, 0, 0), job(1 << 20, 8)).kind, BackendKind::cpu);  // 0.84 s > 25% of 0.84 s
  EXPECT_EQ(auto_rule(rates(100e6, 0, 0, 0), job(kFrame, 20)).kind, BackendKind::cpu);  // 52 ms: the start dominates
}

// The promise: given measurements within a factor e of the truth (each
// rate and each fixed cost), the picked backend's true cost is at most e^2
// times the other's; at e = 1.1 that is 1.21 < 1.25. Random jobs and rates.
TEST(AutoRule, NeverPicksABackendMoreThanAQuarterSlowerWithTenPercentErrors) {
  std::mt19937_64 rng(39);
  std::uniform_real_distribution<double> log_rate(std::log(1e6), std::log(1e10)), log_fixed(std::log(1e-3), std::log(2.0)),
      noise(1 / 1.1, 1.1), log_pixels(std::log(64.0 * 64), std::log(4096.0 * 4096));
  std::uniform_int_distribution<int> frames(1, 5000);
  int vulkan = 0;
  for (int k = 0; k < 100000; ++k) {
    const BackendRates truth = rates(std::exp(log_rate(rng)), std::exp(log_rate(rng)), std::exp(log_fixed(rng)),
                                     std::exp(log_fixed(rng)));
    const BackendRates measured =
        rates(truth.cpu_pixels_per_second * noise(rng), truth.vulkan_pixels_per_second * noise(rng),
              truth.vulkan_open_seconds * noise(rng), truth.vulkan_compile_seconds * noise(rng));
    const RegionJob j = job(std::exp(log_pixels(rng)), frames(rng));
    const double n = j.pixels * j.frames;
    const double cpu = n / truth.cpu_pixels_per_second;
    const double vk = truth.vulkan_open_seconds + truth.vulkan_compile_seconds + n / truth.vulkan_pixels_per_second;
    const bool picked_vulkan = auto_rule(measured, j).kind == BackendKind::vulkan;
    vulkan += picked_vulkan;
    const double picked = picked_vulkan ? vk : cpu, other = picked_vulkan ? cpu : vk;
    ASSERT_LE(picked, 1.25 * other) << "case " << k;
  }
  EXPECT_GT(vulkan, 10000);  // both sides are exercised
  EXPECT_LT(vulkan, 90000);
}

TEST(AutoRule, CandidateDevice) {
  const std::vector<ListedDevice> listed = {{"llvmpipe (LLVM 15.0.6, 256 bits)", true}, {"NVIDIA H200", false}};
  EXPECT_EQ(auto_backend_device(listed), "NVIDIA H200");
  EXPECT_EQ(auto_backend_device(listed, "LLVMpipe"), listed[0].name);
  EXPECT_EQ(auto_backend_device({listed[0]}), "");
  EXPECT_EQ(auto_backend_device(listed, "radeon"), "");
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("cmr_backend_choice_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(BackendRatesFile, KeepsEachDeviceAndSkipsDamagedLines) {
  const std::string dir = fresh_dir("rates").string();
  EXPECT_EQ(load_backend_rates(dir, "A").cpu_pixels_per_second, 0);
  ASSERT_TRUE(store_backend_rates(dir, "Device A", rates(5e7, 2e8, 0.04, 0.03)));
  ASSERT_TRUE(store_backend_rates(dir, "Device B", rates(6e7, 3e8, 0.05, 0.01)));
  const BackendRates a = load_backend_rates(dir, "Device A"), b = load_backend_rates(dir, "Device B");
  EXPECT_DOUBLE_EQ(a.vulkan_pixels_per_second, 2e8);
  EXPECT_DOUBLE_EQ(a.vulkan_open_seconds, 0.04);
  EXPECT_DOUBLE_EQ(b.vulkan_compile_seconds, 0.01);
  EXPECT_DOUBLE_EQ(a.cpu_pixels_per_second, 6e7);  // one CPU line: the latest
  EXPECT_EQ(load_backend_rates(dir, "Device").vulkan_pixels_per_second, 0);  // names match whole
  {
    std::ofstream out(fs::path(dir) / "backend-rates.txt", std::ios::app);
    out << "vulkan nonsense\ncpu\nvulkan -1 0 0 Device C\n\x01\x02garbage\n";
  }
  EXPECT_DOUBLE_EQ(load_backend_rates(dir, "Device B").vulkan_pixels_per_second, 3e8);
  EXPECT_EQ(load_backend_rates(dir, "Device C").vulkan_pixels_per_second, 0);
  EXPECT_FALSE(store_backend_rates("/proc/cmr-cannot-write-here", "X", a));
}

TEST(PipelineCacheHeader, OnlyThisDevicesHeaderIsUsed) {
  const uint8_t uuid[VK_UUID_SIZE] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  std::vector<std::byte> data(48);
  const uint32_t words[4] = {32, VK_PIPELINE_CACHE_HEADER_VERSION_ONE, 0x10de, 0x2335};
  std::memcpy(data.data(), words, 16);
  std::memcpy(data.data() + 16, uuid, 16);
  EXPECT_TRUE(pipeline_cache_matches(data, 0x10de, 0x2335, uuid));
  EXPECT_FALSE(pipeline_cache_matches(data, 0x10de, 0x2336, uuid));  // another device
  EXPECT_FALSE(pipeline_cache_matches(data, 0x1002, 0x2335, uuid));  // another vendor
  uint8_t other[VK_UUID_SIZE] = {};
  EXPECT_FALSE(pipeline_cache_matches(data, 0x10de, 0x2335, other));  // another driver build
  EXPECT_FALSE(pipeline_cache_matches(std::span(data).first(31), 0x10de, 0x2335, uuid));  // truncated
  std::vector<std::byte> bad = data;
  bad[4] = std::byte{2};  // header version
  EXPECT_FALSE(pipeline_cache_matches(bad, 0x10de, 0x2335, uuid));
  bad = data;
  bad[0] = std::byte{100};  // header longer than the data
  EXPECT_FALSE(pipeline_cache_matches(bad, 0x10de, 0x2335, uuid));
}

// ---- On the test device (lavapipe by default).

RegionProblem fig2_512() {
  const BSpline cubic = read_spline_file(fs::path(CMR_SOURCE_DIR) / "examples/figures/fig2.json");
  RegionRequest r;
  r.point = 1;
  r.width = r.height = 512;
  r.max_depth = 10;
  return RegionProblem::make(cubic, r);
}

BackendChoice choice_of(BackendKind kind, const std::string& dir) {
  BackendChoice c;
  c.kind = kind;
  c.device = kind == BackendKind::cpu ? "" : cmr::vk::test::device_under_test();
  c.cache_dir = dir;
  return c;
}

/// Seconds of one one-shot render on a fresh backend (device start and
/// pipeline creation included for Vulkan), the cache directory warm.
double one_shot(BackendKind kind, const std::string& dir, const RegionProblem& p) {
  const auto t0 = Clock::now();
  auto b = make_region_backend(choice_of(kind, dir));
  const RegionResult r = b->render(p);
  EXPECT_EQ(r.size(), 512u * 512u);
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

TEST(AutoOnDevice, OneShot512IsNeverAQuarterSlowerThanTheOtherBackend) {
  const std::string dir = fresh_dir("oneshot").string();
  const RegionProblem p = fig2_512();
  // Calibration, as runs with --backend cpu and --backend vulkan leave it in
  // the cache directory.
  for (int k = 0; k < 2; ++k) {
    make_region_backend(choice_of(BackendKind::cpu, dir))->render(p);
    make_region_backend(choice_of(BackendKind::vulkan, dir))->render(p);
  }
  auto listed = enumerate_devices();
  ASSERT_TRUE(listed);
  const std::string device = auto_backend_device(
      [&] {
        std::vector<ListedDevice> l;
        for (const DeviceInfo& d : listed.value()) l.push_back({d.name, d.type == VK_PHYSICAL_DEVICE_TYPE_CPU});
        return l;
      }(),
      cmr::vk::test::device_under_test());
  ASSERT_FALSE(device.empty());
  const BackendRates measured = load_backend_rates(dir, device);
  ASSERT_GT(measured.cpu_pixels_per_second, 0);
  ASSERT_GT(measured.vulkan_pixels_per_second, 0);
  ASSERT_GT(measured.vulkan_open_seconds, 0);
  const AutoDecision d = auto_rule(measured, job(kFrame, 1));

  // The one-shot costs themselves, interleaved, best of 3 each.
  double cpu = 1e9, vk = 1e9;
  for (int k = 0; k < 3; ++k) {
    cpu = std::min(cpu, one_shot(BackendKind::cpu, dir, p));
    vk = std::min(vk, one_shot(BackendKind::vulkan, dir, p));
  }
  const double picked = d.kind == BackendKind::vulkan ? vk : cpu, other = d.kind == BackendKind::vulkan ? cpu : vk;
  std::printf("one-shot 512^2 fig2 P1 D=10: cpu %.4f s, vulkan %.4f s (estimates %.4f / %.4f), auto picks %s\n", cpu,
              vk, d.cpu_seconds, d.vulkan_seconds, d.kind == BackendKind::vulkan ? "vulkan" : "cpu");
  EXPECT_LE(picked, 1.25 * other);

  // And automatic itself, with --device naming the device under test, follows the rule.
  std::vector<std::string> notes;
  auto autob = make_region_backend(choice_of(BackendKind::automatic, dir), [&](const std::string& n) { notes.push_back(n); });
  autob->render(p);
  EXPECT_EQ(autob->name(), d.kind == BackendKind::vulkan ? "vulkan" : "cpu");
  EXPECT_TRUE(notes.empty());
}

TEST(AutoOnDevice, InjectedMeasurementsDecide) {
  const std::string dir = fresh_dir("injected").string();
  const RegionProblem p = fig2_512();
  BackendChoice c = choice_of(BackendKind::automatic, dir);
  c.rates = rates(1e6, 1e12, 0, 0);  // the device measured far faster
  auto fast = make_region_backend(c);
  const RegionResult rv = fast->render(p);
  EXPECT_EQ(fast->name(), "vulkan");
  c.rates = rates(1e12, 1e6, 0, 0);
  auto slow = make_region_backend(c);
  const RegionResult rc = slow->render(p);
  EXPECT_EQ(slow->name(), "cpu");
  EXPECT_EQ(rv.labels, rc.labels);
}

TEST(AutoOnDevice, AFailingDeviceIsReportedAsTheCpuThatRendered) {
  const std::string dir = fresh_dir("autofault").string();
  const RegionProblem p = fig2_512();
  BackendChoice c = choice_of(BackendKind::automatic, dir);
  c.rates = rates(1e6, 1e12, 0, 0);  // picks the device
  c.fault = InjectedFault::device_lost;
  std::vector<std::string> notes;
  auto b = make_region_backend(c, [&](const std::string& n) { notes.push_back(n); });
  EXPECT_EQ(b->name(), "vulkan");  // what it would pick; nothing rendered yet
  EXPECT_EQ(b->render(p).labels, CpuRegionBackend().render(p).labels);
  EXPECT_EQ(b->name(), "cpu");
  EXPECT_EQ(notes.size(), 1u);
}

// ---- Faults: one note, the CPU backend's labels.

class Fault : public ::testing::TestWithParam<InjectedFault> {};

TEST_P(Fault, GivesOneNoteAndTheCpuAnswer) {
  const std::string dir = fresh_dir("fault").string();
  const RegionProblem p = fig2_512();
  const RegionResult want = CpuRegionBackend().render(p);
  BackendChoice c = choice_of(BackendKind::vulkan, dir);
  c.fault = GetParam();
  std::vector<std::string> notes;
  auto b = make_region_backend(c, [&](const std::string& n) { notes.push_back(n); });
  const RegionResult got = b->render(p);
  EXPECT_EQ(got.labels, want.labels);
  EXPECT_EQ(b->name(), "cpu");
  b->render(p);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("the Vulkan backend failed"), std::string::npos) << notes[0];
  EXPECT_EQ(notes[0].find('\n'), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Injected, Fault,
                         ::testing::Values(InjectedFault::device_lost, InjectedFault::out_of_memory,
                                           InjectedFault::pipeline_rejected),
                         [](const ::testing::TestParamInfo<InjectedFault>& p) -> std::string {
                           switch (p.param) {
                             case InjectedFault::device_lost: return "DeviceLost";
                             case InjectedFault::out_of_memory: return "OutOfMemory";
                             case InjectedFault::pipeline_rejected: return "PipelineRejected";
                             case InjectedFault::none: break;
                           }
                           return "None";
                         });

TEST(PipelineCacheFile, DamagedFileIsOneNoteThenRebuilt) {
  const std::string dir = fresh_dir("cache").string();
  const RegionProblem p = fig2_512();
  const RegionResult want = CpuRegionBackend().render(p);
  auto created = VulkanRegionBackend::create({.device = cmr::vk::test::device_under_test(), .cache_dir = dir});
  ASSERT_TRUE(created);
  const std::string file = created.value().cache_file();
  created.value().render(p);
  ASSERT_TRUE(fs::exists(file)) << file;
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << "not a pipeline cache at all, not even its header";
  }
  std::vector<std::string> notes;
  auto b = make_region_backend(choice_of(BackendKind::vulkan, dir), [&](const std::string& n) { notes.push_back(n); });
  EXPECT_EQ(b->render(p).labels, want.labels);
  EXPECT_EQ(b->name(), "vulkan");
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("pipeline cache"), std::string::npos) << notes[0];
  // Rebuilt: the next run reads it without a note.
  notes.clear();
  auto again = make_region_backend(choice_of(BackendKind::vulkan, dir), [&](const std::string& n) { notes.push_back(n); });
  again->render(p);
  EXPECT_TRUE(notes.empty()) << notes.front();
}

// Through cmr: exit 0, one line on stderr, the CPU's labels.
TEST(FaultCli, EachFaultExitsZeroWithOneLine) {
  const fs::path dir = fresh_dir("cli");
  const std::string fig2 = std::string(CMR_SOURCE_DIR) + "/examples/figures/fig2.json";
  const std::string env = "XDG_CACHE_HOME=" + dir.string() + " ";
  const auto cpu = cmr::test::run_captured(env + CMR_BINARY + " region " + fig2 + " --point 1 --size 64x64 --backend cpu --labels " +
                                           (dir / "cpu.pgm").string());
  ASSERT_EQ(cpu.code, 0) << cpu.err;
  for (const std::string fault : {"device_lost", "out_of_memory", "pipeline_rejected"}) {
    const auto r = cmr::test::run_captured(env + "CMR_VK_FAULT=" + fault + " " + CMR_BINARY + " region " + fig2 +
                                           " --point 1 --size 64x64 --backend vulkan --labels " +
                                           (dir / (fault + ".pgm")).string());
    EXPECT_EQ(r.code, 0) << fault << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("note: the Vulkan backend failed", 0), 0u) << r.err;
    EXPECT_NE(r.out.find("\"backend\":\"cpu\""), std::string::npos) << r.out;
    EXPECT_EQ(cmr::test::slurp(dir / (fault + ".pgm")), cmr::test::slurp(dir / "cpu.pgm")) << fault;
  }
  // A damaged pipeline cache file: one note, Vulkan still renders.
  for (const auto& e : fs::directory_iterator(dir / "cmr"))
    if (e.path().filename().string().rfind("vulkan-pipelines-", 0) == 0) fs::remove(e.path());
  cmr::test::run_captured(env + CMR_BINARY + " region " + fig2 + " --point 1 --size 64x64 --backend vulkan");
  int damaged = 0;
  for (const auto& e : fs::directory_iterator(dir / "cmr"))
    if (e.path().filename().string().rfind("vulkan-pipelines-", 0) == 0) {
      std::ofstream(e.path(), std::ios::binary | std::ios::trunc) << "garbage";
      ++damaged;
    }
  ASSERT_EQ(damaged, 1);
  const auto r = cmr::test::run_captured(env + CMR_BINARY + " region " + fig2 + " --point 1 --size 64x64 --backend vulkan --labels " +
                                         (dir / "damaged.pgm").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("pipeline cache"), std::string::npos) << r.err;
  EXPECT_EQ(cmr::test::slurp(dir / "damaged.pgm"), cmr::test::slurp(dir / "cpu.pgm"));
}

}  // namespace
}  // namespace cmr::vk
