#include "vk/backend_choice.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <system_error>
#include <utility>

#include <unistd.h>

#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/parallel.hpp"
#include "vk/context.hpp"
#include "vk/space_region_vk.hpp"

namespace cmr::vk {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

double frame_pixels(const RegionProblem& p) {
  return static_cast<double>(p.request().width) * static_cast<double>(p.request().height);
}

constexpr const char* kRatesFile = "backend-rates.txt";

/// The names of the Vulkan devices backend-rates.txt holds.
std::vector<std::string> stored_vulkan_devices(const std::string& cache_dir) {
  std::vector<std::string> names;
  if (cache_dir.empty()) return names;
  std::ifstream in(std::filesystem::path(cache_dir) / kRatesFile);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string kind, name;
    double pps = 0, open = 0, compile = 0;
    if (!(s >> kind) || kind != "vulkan" || !(s >> pps >> open >> compile)) continue;
    std::getline(s >> std::ws, name);
    if (!name.empty()) names.push_back(name);
  }
  return names;
}

/// Frames smaller than this say more about fixed costs than about a rate.
constexpr double kMinMeasuredPixels = 16384;

/// A new measurement folded into the kept one: their geometric mean, so one
/// disturbed frame moves a rate by at most the square root of its error.
double fold(double kept, double measured) { return kept > 0 ? std::sqrt(kept * measured) : measured; }

/// The rates a backend reads and updates, shared by the backends one
/// make_region_backend builds; written back to the cache file when it
/// changes (unless they were injected). Thread-safe, as the CPU backend is
/// (callers may render on it from several threads).
class RateBook {
 public:
  RateBook(std::string dir, std::optional<BackendRates> injected)
      : dir_(std::move(dir)), injected_(injected.has_value()), rates_(injected.value_or(BackendRates{})) {
    if (!injected_) rates_ = load_backend_rates(dir_, "");
  }
  BackendRates rates() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return rates_;
  }
  /// The Vulkan device the Vulkan rates belong to (known at its listing or opening).
  void set_device(const std::string& name) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (name == device_) return;
    device_ = name;
    if (injected_) return;
    const BackendRates kept = load_backend_rates(dir_, device_);
    rates_.vulkan_pixels_per_second = kept.vulkan_pixels_per_second;
    rates_.vulkan_open_seconds = kept.vulkan_open_seconds;
    rates_.vulkan_compile_seconds = kept.vulkan_compile_seconds;
  }
  /// Whether auto_rule could pick some Vulkan device for `job`: an
  /// unmeasured one (exploration), or one the cache file (or the injected
  /// rates) holds. False when the CPU is unmeasured.
  bool vulkan_possible(const RegionJob& job) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (rates_.cpu_pixels_per_second <= 0) return false;
    BackendRates r;
    r.cpu_pixels_per_second = rates_.cpu_pixels_per_second;
    if (auto_rule(r, job).kind == BackendKind::vulkan) return true;  // exploring an unmeasured device
    if (injected_) return auto_rule(rates_, job).kind == BackendKind::vulkan;
    for (const std::string& name : stored_vulkan_devices(dir_)) {
      BackendRates kept = load_backend_rates(dir_, name);
      kept.cpu_pixels_per_second = rates_.cpu_pixels_per_second;
      if (auto_rule(kept, job).kind == BackendKind::vulkan) return true;
    }
    return false;
  }
  void cpu_frame(double pixels, double seconds) {
    if (pixels < kMinMeasuredPixels || seconds <= 0) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    rates_.cpu_pixels_per_second = fold(rates_.cpu_pixels_per_second, pixels / seconds);
    save();
  }
  void vulkan_open(double seconds) {
    const std::lock_guard<std::mutex> lock(mutex_);
    rates_.vulkan_open_seconds = fold(rates_.vulkan_open_seconds, seconds);
    save();
  }
  void vulkan_frame(double pixels, double seconds, double compile_seconds) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (compile_seconds > 0) rates_.vulkan_compile_seconds = fold(rates_.vulkan_compile_seconds, compile_seconds);
    if (pixels >= kMinMeasuredPixels && seconds > 0)
      rates_.vulkan_pixels_per_second = fold(rates_.vulkan_pixels_per_second, pixels / seconds);
    save();
  }

 private:
  void save() {
    if (!injected_ && !dir_.empty()) store_backend_rates(dir_, device_, rates_);
  }
  mutable std::mutex mutex_;
  std::string dir_, device_;
  bool injected_;
  BackendRates rates_;  // guarded by mutex_, as is device_
};

/// The CPU backend, its frames measured.
class MeasuredCpuBackend final : public RegionBackend {
 public:
  explicit MeasuredCpuBackend(std::shared_ptr<RateBook> book) : book_(std::move(book)) {}
  RegionResult render(const RegionProblem& problem) override {
    const auto t0 = Clock::now();
    RegionResult r = cpu_.render(problem);
    book_->cpu_frame(frame_pixels(problem), since(t0));
    return r;
  }
  std::string name() const override { return "cpu"; }

 private:
  std::shared_ptr<RateBook> book_;
  CpuRegionBackend cpu_;
};

/// The Vulkan backend, opened at its first render. Opening failures become
/// EnvironmentError with what to do about them. A failure after it opened
/// (device lost, out of memory, a rejected pipeline) is announced once and
/// the CPU backend renders that frame and every later one.
class DeferredVulkanBackend final : public RegionBackend {
 public:
  DeferredVulkanBackend(VulkanRegionOptions options, std::string loader_selection, std::shared_ptr<RateBook> book,
                        BackendNote note)
      : options_(std::move(options)), loader_selection_(std::move(loader_selection)), book_(std::move(book)),
        note_(std::move(note)), cpu_(book_) {}
  RegionResult render(const RegionProblem& problem) override {
    if (failed_) return cpu_.render(problem);
    if (!backend_) open();
    const auto t0 = Clock::now();
    auto r = backend_->try_render(problem);
    if (!r) {
      if (r.error().code == Errc::size_unsupported) throw InputFieldError(r.error().message);
      // A device that lacks what was asked (fp64) is the user's choice to
      // change (--precision fp32): an environment error, as before.
      if (r.error().code == Errc::missing_feature) throw RegionFailure(r.error());
      failed_ = true;
      announce("the Vulkan backend failed (" + r.error().message + "), so the CPU backend renders");
      return cpu_.render(problem);
    }
    book_->vulkan_frame(frame_pixels(problem), since(t0) - r.value().setup_seconds, r.value().setup_seconds);
    note_cache();
    return r.take();
  }
  std::string name() const override { return failed_ ? "cpu" : "vulkan"; }
  bool ready() const { return backend_.has_value() && backend_->pipeline_seconds() > 0; }

 private:
  void open() {
    auto created = VulkanRegionBackend::create(options_);
    if (!created) {
      std::string message = created.error().message;
      if (created.error().code == Errc::no_device && !loader_selection_.empty()) {
        const std::size_t at = message.find(';');
        message.insert(at == std::string::npos ? message.size() : at,
                       " (" + loader_selection_ + "; check that the file exists)");
      }
      if (message.find("VK_DRIVER_FILES") == std::string::npos)
        message += " (for lavapipe: install mesa-vulkan-drivers or export "
                   "VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json)";
      throw EnvironmentFieldError(message + "; or use " + field("backend") + " cpu");
    }
    backend_.emplace(created.take());
    book_->set_device(backend_->device().name);
    book_->vulkan_open(backend_->open_seconds());
    note_cache();
  }
  void note_cache() {
    if (backend_ && !backend_->cache_note().empty() && !cache_noted_) {
      cache_noted_ = true;
      announce(backend_->cache_note());
    }
  }
  void announce(const std::string& line) const {
    if (note_) note_(line);
  }
  VulkanRegionOptions options_;
  std::string loader_selection_;
  std::shared_ptr<RateBook> book_;
  BackendNote note_;
  MeasuredCpuBackend cpu_;
  std::optional<VulkanRegionBackend> backend_;
  bool failed_ = false, cache_noted_ = false;
};

VulkanRegionOptions vulkan_options(const BackendChoice& choice) {
  VulkanRegionOptions o;
  o.device = choice.device;
  o.precision = choice.precision;
  o.cache_dir = choice.cache_dir;
  o.fault = choice.fault;
  return o;
}

/// auto_backend_device on what the loader lists; empty when there is no
/// loader, driver or device at all.
std::string candidate_device(const std::string& wanted) {
  auto devices = enumerate_devices();
  if (!devices) return {};
  std::vector<ListedDevice> listed;
  for (const DeviceInfo& d : devices.value()) listed.push_back({d.name, d.type == VK_PHYSICAL_DEVICE_TYPE_CPU});
  return auto_backend_device(listed, wanted);
}

/// BackendKind::automatic: auto_rule per frame between the CPU backend and
/// the candidate device (see the header comment).
class AutoBackend final : public RegionBackend {
 public:
  AutoBackend(BackendChoice choice, BackendNote note, std::shared_ptr<RateBook> book)
      : choice_(std::move(choice)), note_(std::move(note)), book_(std::move(book)), cpu_(book_) {}
  RegionResult render(const RegionProblem& problem) override {
    RegionBackend& b = pick(frame_pixels(problem), true);
    if (&b == vulkan_.get()) {
      try {
        RegionResult r = b.render(problem);
        last_ = b.name();  // "cpu" when the device failed during the frame
        return r;
      } catch (const InputError&) {
        throw;
      } catch (const EnvironmentError& e) {  // the device would not open, or lacks fp64
        vulkan_failed_ = true;
        if (note_) note_("the Vulkan device cannot render (" + marked_text(e) + "), so the CPU backend renders");
        last_ = "cpu";
        return cpu_.render(problem);
      }
    }
    last_ = b.name();
    return b.render(problem);
  }
  std::string name() const override {
    if (!last_.empty()) return last_;
    return const_cast<AutoBackend*>(this)->pick(512.0 * 512.0, false).name();
  }

 private:
  /// The backend for a frame of `pixels`; `frame`: one is about to render.
  RegionBackend& pick(double pixels, bool frame) {
    const int expected = choice_.frames > 0 ? choice_.frames : kManyFrames;
    RegionJob job;
    job.pixels = pixels;
    job.frames = std::max(1, expected - rendered_);
    if (frame) ++rendered_;
    if (!listed_) {
      // Asking the loader costs an instance (tens of milliseconds, more than
      // a small frame): only when some device could win this job.
      if (!book_->vulkan_possible(job)) return cpu_;
      listed_ = true;
      device_ = candidate_device(choice_.device);
      if (device_.empty()) {
        if (note_) note_(kCpuFallbackNote);
      } else {
        book_->set_device(device_);
        BackendChoice c = choice_;
        c.device = device_;
        vulkan_ = std::make_shared<DeferredVulkanBackend>(vulkan_options(c), c.loader_selection, book_, note_);
      }
    }
    if (!vulkan_ || vulkan_failed_) return cpu_;
    job.vulkan_open = vulkan_->ready();
    const AutoDecision d = auto_rule(book_->rates(), job);
    if (d.kind == BackendKind::vulkan) return *vulkan_;
    return cpu_;
  }
  BackendChoice choice_;
  BackendNote note_;
  std::shared_ptr<RateBook> book_;
  MeasuredCpuBackend cpu_;
  std::shared_ptr<DeferredVulkanBackend> vulkan_;
  bool listed_ = false, vulkan_failed_ = false;
  std::string device_, last_;
  int rendered_ = 0;
};

}  // namespace

AutoDecision auto_rule(const BackendRates& r, const RegionJob& job) {
  AutoDecision d;
  if (r.cpu_pixels_per_second <= 0) return d;  // the CPU measures itself at no fixed cost
  const double work = job.pixels * std::max(1, job.frames);
  d.cpu_seconds = work / r.cpu_pixels_per_second;
  const double fixed = job.vulkan_open ? 0 : r.vulkan_open_seconds + r.vulkan_compile_seconds;
  if (r.vulkan_pixels_per_second > 0) {
    d.vulkan_seconds = fixed + work / r.vulkan_pixels_per_second;
    if (d.vulkan_seconds < d.cpu_seconds) d.kind = BackendKind::vulkan;
    return d;
  }
  // Not measured: one exploratory frame at the pessimistic priors.
  const double prior_fixed = job.vulkan_open ? 0 : std::max(fixed, kPriorVulkanFixedSeconds);
  const double explore = prior_fixed + job.pixels * kPriorVulkanSlowdown / r.cpu_pixels_per_second;
  if (job.frames > 1 && explore <= kExploreShare * d.cpu_seconds) {
    d.kind = BackendKind::vulkan;
    d.explore = true;
  }
  return d;
}

std::string auto_backend_device(const std::vector<ListedDevice>& devices, const std::string& wanted) {
  const std::string w = lower(wanted);
  for (const ListedDevice& d : devices)
    if (w.empty() ? !d.cpu : lower(d.name).find(w) != std::string::npos) return d.name;
  return {};
}

BackendRates load_backend_rates(const std::string& cache_dir, const std::string& device) {
  BackendRates r;
  if (cache_dir.empty()) return r;
  std::ifstream in(std::filesystem::path(cache_dir) / kRatesFile);
  const std::string cores = std::to_string(available_cores());
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string kind;
    s >> kind;
    if (kind == "cpu") {
      std::string n;
      double pps = 0;
      if (s >> n >> pps && n == cores && std::isfinite(pps) && pps > 0) r.cpu_pixels_per_second = pps;
    } else if (kind == "vulkan") {
      double pps = 0, open = 0, compile = 0;
      std::string name;
      if (!(s >> pps >> open >> compile)) continue;
      std::getline(s >> std::ws, name);
      if (name != device || device.empty()) continue;
      if (std::isfinite(pps) && pps >= 0 && std::isfinite(open) && open >= 0 && std::isfinite(compile) && compile >= 0) {
        r.vulkan_pixels_per_second = pps;
        r.vulkan_open_seconds = open;
        r.vulkan_compile_seconds = compile;
      }
    }
  }
  return r;
}

bool store_backend_rates(const std::string& cache_dir, const std::string& device, const BackendRates& rates) {
  if (cache_dir.empty()) return false;
  const std::filesystem::path file = std::filesystem::path(cache_dir) / kRatesFile;
  const std::string cores = std::to_string(available_cores());
  std::vector<std::string> kept;
  {
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream s(line);
      std::string kind, n;
      s >> kind;
      if (kind == "cpu" && s >> n && n != cores) kept.push_back(line);
      if (kind == "vulkan") {
        double a = 0, b = 0, c = 0;
        std::string name;
        if (!(s >> a >> b >> c)) continue;
        std::getline(s >> std::ws, name);
        if (name != device || device.empty()) kept.push_back(line);
      }
    }
  }
  std::ostringstream out;
  out.precision(6);
  out << "# cmr backend rates: cpu CORES PIXELS_PER_S | vulkan PIXELS_PER_S OPEN_S COMPILE_S NAME\n";
  if (rates.cpu_pixels_per_second > 0) out << "cpu " << cores << ' ' << rates.cpu_pixels_per_second << '\n';
  if (!device.empty() && device.find('\n') == std::string::npos)
    out << "vulkan " << rates.vulkan_pixels_per_second << ' ' << rates.vulkan_open_seconds << ' '
        << rates.vulkan_compile_seconds << ' ' << device << '\n';
  for (const std::string& l : kept)
    if (l.rfind('#', 0) != 0) out << l << '\n';
  std::error_code ec;
  std::filesystem::create_directories(cache_dir, ec);
  std::filesystem::path part = file;
  part += ".part" + std::to_string(::getpid());
  {
    std::ofstream o(part, std::ios::trunc);
    o << out.str();
    if (!o) ec = std::make_error_code(std::errc::io_error);
  }
  if (!ec) std::filesystem::rename(part, file, ec);
  const bool written = !ec;
  if (!written) std::filesystem::remove(part, ec);
  return written;
}

std::shared_ptr<RegionBackend> make_region_backend(const BackendChoice& choice, BackendNote note) {
  auto book = std::make_shared<RateBook>(choice.cache_dir, choice.rates);
  switch (choice.kind) {
    case BackendKind::cpu:
      return std::make_shared<MeasuredCpuBackend>(book);
    case BackendKind::automatic:
      return std::make_shared<AutoBackend>(choice, std::move(note), book);
    case BackendKind::vulkan:
      return std::make_shared<DeferredVulkanBackend>(vulkan_options(choice), choice.loader_selection, book,
                                                     std::move(note));
  }
  CMR_CHECK(false);
  return nullptr;
}

std::shared_ptr<SpaceRegionBackend> make_space_region_backend(const BackendChoice& choice) {
  switch (choice.kind) {
    case BackendKind::cpu:
    case BackendKind::automatic:
      return std::make_shared<CpuSpaceRegionBackend>();
    case BackendKind::vulkan: {
      SpaceRegionVkOptions o;
      o.device = choice.device;
      return std::make_shared<VulkanSpaceRegionBackend>(o);
    }
  }
  CMR_CHECK(false);
  return nullptr;
}

}  // namespace cmr::vk
