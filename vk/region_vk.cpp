#include "vk/region_vk.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <span>
#include <system_error>

#include <unistd.h>

#include "region/region_setup.hpp"
#include "shaders/region_layout.h"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"
#include "vk/buffer_packer.hpp"
#include "vk/internal.hpp"

#include "region_fp32_comp.h"
#include "region_fp64_comp.h"
#include "region_pixels_fp32_comp.h"
#include "region_pixels_fp64_comp.h"
#include "region_second_fp64_comp.h"
#include "region_tiles_fp32_comp.h"
#include "region_tiles_fp64_comp.h"

namespace cmr::vk {
namespace {

using namespace layout;
using detail::BufferPacker;
using cmr::backend::RegionEntry;
using cmr::backend::RegionJoint;
using cmr::backend::RegionSetup;

// Blocks the host leaves undecided at this side length go to the device
// (the culled share, the share of a CPU device). At 4 x 4 the device
// classified 2-3.5 times the pixels of 2 x 2 proofs on lavapipe, each
// several times dearer there than a host proof's share of it.
constexpr int kDeviceBlock = 2;
// Pixels per run, so that no storage buffer passes the 2^27 bytes every
// device allows (maxStorageBufferRange): a listed pixel takes 16 bytes of
// list, a pixel of the whole share one byte of label map and one of depth.
// The whole share's 2^24 pixels are 2^18 tiles, 4096 groups of the tile
// pass (its pixel pass takes a group per queued tile, up to the 65535 of a
// dispatch every device allows, and those loop over the rest).
constexpr std::size_t kListedPerRun = std::size_t{1} << 22, kWholePerRun = std::size_t{1} << 24;
// Flagged pixels a run of the whole share lists for the host (more: the
// host finds them in the label map).
constexpr uint32_t kFlaggedListed = 1u << 16;

static_assert(cmr::kRegionLabelCodes < PACKED_UNCERTAIN && cmr::kSplitLabelCodes < PACKED_UNCERTAIN &&
                  cmr::kAlternatingLabelCodes < PACKED_UNCERTAIN && cmr::kPieceLabelCodes < PACKED_UNCERTAIN,
              "a packed label byte of 255 must mean 'the host decides'");

uint32_t flags_of(const SegmentClass& c, Mode mode) {
  uint32_t f = 0;
  switch (c.monotonicity.curvature) {
    case Curvature::increasing: f |= FLAG_INC; break;
    case Curvature::decreasing: f |= FLAG_DEC; break;
    case Curvature::non_monotone: f |= FLAG_NONE; break;
    case Curvature::undecided: f |= FLAG_UNDECIDED; break;
    case Curvature::constant: break;
  }
  if (mode == Mode::cmr) {
    switch (c.inflection.inflection) {
      case Inflection::present: f |= FLAG_NONE; break;
      case Inflection::undecided: f |= FLAG_UNDECIDED; break;
      case Inflection::none: f |= c.inflection.kappa_sign > 0 ? FLAG_KPOS : FLAG_KNEG; break;
    }
  }
  return f;
}

// Polynomial coefficients as the device will see them. All zeros must mean an
// exact zero (the shader then trusts the sign), and rounding to float must
// keep a relative error: a coefficient that would be subnormal or zero in
// float, or overflow, turns the polynomial into NaN, whose signs are never
// certain (those pixels go to the host).
template <std::size_t K>
std::array<double, K> for_device(const std::array<double, K>& c, RegionPrecision precision) {
  if (precision == RegionPrecision::fp64) return c;
  bool bad = false;
  for (double v : c)
    bad = bad || (v != 0 && (std::fabs(v) < std::numeric_limits<float>::min() ||
                             std::fabs(v) > std::numeric_limits<float>::max()));
  std::array<double, K> out = c;
  if (bad) out[0] = std::numeric_limits<double>::quiet_NaN();
  return out;
}

}  // namespace

namespace detail {

/// The storage buffer for the shader (shaders/region_layout.h): `pixels`
/// are (column, row) of the image.
std::vector<std::byte> pack_region(const RegionSetup& s, RegionPrecision precision,
                                   std::span<const std::array<int, 2>> pixels, bool every_pixel) {
  const RegionRequest& o = s.options;
  const int N = s.spline().segment_count();
  auto part_of = [&](int seg) { return cmr::group_of(s.cuts, seg); };
  const cmr::backend::Labels kind = cmr::backend::labels_of(o);

  BufferPacker p(HDR_WORDS, precision);
  p.hdr[HDR_WIDTH] = static_cast<uint32_t>(o.width);
  p.hdr[HDR_HEIGHT] = static_cast<uint32_t>(o.height);
  p.hdr[HDR_MODE] = o.mode == Mode::cmr ? 1 : 0;
  p.hdr[HDR_LABELS] = kind == cmr::backend::Labels::each_piece    ? LABELS_EACH_PIECE
                     : kind == cmr::backend::Labels::alternating ? LABELS_ALTERNATING
                     : kind == cmr::backend::Labels::split     ? LABELS_SPLIT
                                                              : LABELS_PLAIN;
  p.hdr[HDR_DEPTH] = static_cast<uint32_t>(o.max_depth);
  p.hdr[HDR_FIXED_LEVEL0_NONE] = s.fixed_level0_none ? 1 : 0;
  p.hdr[HDR_PIECE_LEVELS] = static_cast<uint32_t>(s.piece_levels);
  const int pieces = (2 << s.piece_levels) - 1;

  // dx, dy of every column and row, exactly as cmr::classify_position forms them
  // (scaled: kernel_displacement).
  p.hdr[HDR_DX_OFFSET] = p.size();
  for (int i = 0; i < o.width; ++i)
    p.values(cmr::backend::kernel_displacement(s, pixel_center(*o.view, o.width, o.height, i, 0).x - s.anchor.x), 0);
  p.hdr[HDR_DY_OFFSET] = p.size();
  for (int j = 0; j < o.height; ++j)
    p.values(cmr::backend::kernel_displacement(s, pixel_center(*o.view, o.width, o.height, 0, j).y - s.anchor.y), 0);

  std::vector<bool> in_entry(N, false), touched(N, false);
  p.hdr[HDR_ENTRIES] = static_cast<uint32_t>(s.entries.size());
  p.hdr[HDR_ENTRY_OFFSET] = p.size();
  for (const RegionEntry& e : s.entries) {
    in_entry[e.segment] = true;
    touched[e.segment] = e.classify;
    p.values(e.part, e.classify ? 1.0 : 0.0);
    for (std::size_t i = 0; i < e.base.size(); ++i) {
      p.bounded(e.base[i].x);
      p.bounded(e.base[i].y);
      p.bounded(e.weight[i]);
    }
    for (int k = 0; k < pieces * e.n_xi; ++k) {
      const std::array<double, 10> c = e.classify ? for_device(e.xi[k], precision) : std::array<double, 10>{};
      for (int m = 0; m < 10; m += 2) p.values(c[m], c[m + 1]);
    }
    for (int k = 0; k < pieces * e.n_nu; ++k) {
      const std::array<double, 3> c = e.classify ? for_device(e.nu[k], precision) : std::array<double, 3>{};
      p.values(c[0], c[1]);
      p.values(c[2], 0);
    }
  }
  // Untouched judged segments and joints strictly inside the judged range
  // whose jump does not vary fold into the groups' flags; varying joints go
  // to the shader. Segments outside the range are ignored.
  std::vector<uint32_t> flags(s.cuts.size() + 1, 0);
  int fixed_depth = 0;
  for (int seg = s.range.first; seg <= s.range.last; ++seg) {
    if (touched[seg]) continue;
    flags[part_of(seg)] |= flags_of(s.fixed()[seg], o.mode);
    fixed_depth = std::max(fixed_depth, s.fixed()[seg].monotonicity.depth);
    if (o.mode == Mode::cmr) fixed_depth = std::max(fixed_depth, s.fixed()[seg].inflection.depth);
  }
  std::vector<bool> varies(s.joints().size() + 1, false);  // the last: a closed spline's seam
  for (const RegionJoint& j : s.varying) varies[j.joint] = true;
  if (s.around && !varies.back()) {  // the seam's fixed jump (detail::RegionSetup::around)
    if (s.seam().jump > 0) flags[0] |= FLAG_UP;
    if (s.seam().jump < 0) flags[0] |= FLAG_DOWN;
  }
  for (std::size_t j = 0; j < s.joints().size(); ++j) {
    const Joint& jt = s.joints()[j];
    if (!cmr::joint_counts(s.range, s.cuts, jt.index) || varies[j]) continue;
    if (jt.jump > 0) flags[part_of(jt.index)] |= FLAG_UP;
    if (jt.jump < 0) flags[part_of(jt.index)] |= FLAG_DOWN;
  }
  p.hdr[HDR_JOINT_OFFSET] = p.size();
  for (const RegionJoint& j : s.varying) {
    p.values(j.left, j.right);
    p.values(j.part, 0);
  }
  p.hdr[HDR_JOINTS] = static_cast<uint32_t>(s.varying.size());
  p.hdr[HDR_LISTED] = static_cast<uint32_t>(pixels.size());
  p.hdr[HDR_DEPTH_PLANE] = every_pixel && o.depth ? 1 : 0;
  if (every_pixel) {
    // Each tile column's and tile row's box (the block proofs' boxes); no
    // tile proofs with a depth map (a tile's pixels may decide at different
    // depths).
    p.hdr[HDR_TILE_PROOFS] = o.depth ? 0 : 1;
    p.hdr[HDR_TILE_X_OFFSET] = p.size();
    for (int i = 0; i < o.width; i += static_cast<int>(TILE))
      p.bounded(cmr::backend::block_columns(s, i, std::min(o.width, i + static_cast<int>(TILE)) - 1));
    p.hdr[HDR_TILE_Y_OFFSET] = p.size();
    for (int j = 0; j < o.height; j += static_cast<int>(TILE))
      p.bounded(cmr::backend::block_rows(s, j, std::min(o.height, j + static_cast<int>(TILE)) - 1));
  }
  p.hdr[HDR_LIST_OFFSET] = p.size();
  for (const auto& [i, j] : pixels) p.values(i, j);
  p.hdr[HDR_PARTS] = static_cast<uint32_t>(flags.size());
  p.hdr[HDR_PART_OFFSET] = p.size();
  for (uint32_t f : flags) p.values(f, 0);
  p.hdr[HDR_FIXED_DEPTH] = static_cast<uint32_t>(fixed_depth);
  return p.bytes();
}

}  // namespace detail

namespace {

// Pixels the device could not certify (row-major indices `at`), decided on
// the host (certified, then exactly), on the worker pool's threads (not
// threads started per frame: most frames flag a few pixels, and starting a
// thread cost more than deciding them); their depths only with a depth map.
void decide_on_host(const RegionSetup& s, const std::vector<std::size_t>& at, cmr::backend::RegionImage& img,
                    int threads) {
  const std::size_t w = static_cast<std::size_t>(img.width);
  std::vector<uint8_t> exact(at.size(), 0);
  cmr::WorkerPool::shared().run(at.size(), threads, [&](std::size_t u) {
    const std::size_t k = at[u];
    const int i = static_cast<int>(k % w), j = static_cast<int>(k / w);
    const cmr::backend::PixelResult pr =
        cmr::backend::classify_position(s, pixel_center(img.view, img.width, img.height, i, j));
    img.labels[k] = pr.label;
    if (s.options.depth) img.depth[k] = pr.depth;
    exact[u] = pr.exact ? 1 : 0;
  });
  for (const uint8_t e : exact) img.exact_pixels += e;
}

// The image decoded from the device's words for the listed pixels; the
// uncertain ones are decided on the host.
void apply_words(const RegionSetup& s, const std::vector<std::array<int, 2>>& pixels,
                 const std::vector<uint32_t>& words, cmr::backend::RegionImage& img, int threads) {
  const RegionRequest& o = s.options;
  std::vector<std::size_t> uncertain;
  for (std::size_t k = 0; k < pixels.size(); ++k) {
    const auto [i, j] = pixels[k];
    const std::size_t at = static_cast<std::size_t>(j) * o.width + i;
    const uint32_t w = words[k];
    if (w & RESULT_UNCERTAIN) {
      uncertain.push_back(at);  // not certified on the device (or deeper than its pieces)
    } else {
      img.labels[at] = static_cast<uint8_t>(w & RESULT_LABEL_MASK);
      img.depth[at] = static_cast<uint8_t>((w >> RESULT_DEPTH_SHIFT) & 0xff);
    }
  }
  decide_on_host(s, uncertain, img, threads);
  if (!o.depth) std::fill(img.depth.begin(), img.depth.end(), 0);
}

}  // namespace

Result<VulkanRegionBackend> VulkanRegionBackend::create(const VulkanRegionOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  ContextOptions co;
  co.device_name = options.device;
  co.require_float64 = false;  // fp64 is checked per render, so fp32 works on any device
  auto context = Context::create(co);
  if (!context) return context.error();
  VulkanRegionBackend b(context.take(), options);
  if (const std::string file = b.cache_file(); !file.empty()) {
    std::ifstream in(file, std::ios::binary);
    if (in) {
      const std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      const auto data = std::as_bytes(std::span<const char>(bytes));
      if (auto r = b.context_.load_pipeline_cache(data); !r) {
        if (r.error().code != Errc::other) return r.error();
        b.cache_note_ = "the Vulkan pipeline cache " + file + " is not this device's or is damaged, so it is rebuilt";
      }
    }
  }
  b.open_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return b;
}

std::string VulkanRegionBackend::cache_file() const {
  if (options_.cache_dir.empty()) return {};
  const VkPhysicalDeviceProperties& p = context_.state()->properties;
  char name[64];
  std::snprintf(name, sizeof name, "vulkan-pipelines-%04x-%04x.bin", p.vendorID, p.deviceID);
  return (std::filesystem::path(options_.cache_dir) / name).string();
}

void VulkanRegionBackend::save_pipeline_cache() {
  const std::string file = cache_file();
  if (file.empty()) return;
  const std::vector<std::byte> data = context_.pipeline_cache_data();
  if (data.empty()) return;
  // Written beside and renamed over, so a reader never sees half a file.
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(file).parent_path(), ec);
  const std::string part = file + ".part" + std::to_string(::getpid());
  {
    std::ofstream out(part, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size()));
    if (!out) ec = std::make_error_code(std::errc::io_error);
  }
  if (!ec) std::filesystem::rename(part, file, ec);
  // A cache that cannot be written (a read-only home) only costs the next
  // run its compile: no note.
  if (ec) std::filesystem::remove(part, ec);
}

DeviceShare VulkanRegionBackend::share() const {
  if (options_.share != DeviceShare::automatic) return options_.share;
  return context_.device().type == VK_PHYSICAL_DEVICE_TYPE_CPU ? DeviceShare::culled : DeviceShare::whole;
}

bool VulkanRegionBackend::cascade() const { return options_.cascade && context_.device().float64; }

Result<ComputePipeline*> VulkanRegionBackend::pipeline_for(const RegionSetup& s, bool deep) {
  const bool cascade = deep && this->cascade();
  // A cascade runs fp32 passes and then fp64; the culled share's cascade is fp64.
  const RegionPrecision precision = cascade ? RegionPrecision::fp32
                                    : options_.cascade ? RegionPrecision::fp64
                                                       : options_.precision;
  const Key key{s.spline().degree(), s.options.max_depth, precision, s.options.mode == Mode::cmr, !s.varying.empty(),
                s.spline().is_rational(), deep, cascade};
  for (auto& [k, pl] : pipelines_)
    if (k == key) return &pl;
  if (options_.fault == InjectedFault::pipeline_rejected)
    return Error{Errc::shader_invalid, VK_ERROR_UNKNOWN,
                 "vkCreateGraphicsPipelines failed: VK_ERROR_UNKNOWN (injected: the driver rejected the pipeline)"};
  const auto t0 = std::chrono::steady_clock::now();
  const uint32_t spec[7] = {static_cast<uint32_t>(key.degree), static_cast<uint32_t>(key.depth), key.cmr ? 1u : 0u,
                            key.joints ? 1u : 0u, key.rational ? 1u : 0u, key.deep ? 1u : 0u,
                            static_cast<uint32_t>(options_.weaken_bound_bits)};
  using Words = std::span<const uint32_t>;
  const bool f64 = precision == RegionPrecision::fp64;
  // The culled share: one pass over the listed pixels. The whole share is a
  // chain: the tile pass, then the pixel pass over the tiles it queued, then
  // (a cascade) the fp64 pass over the pixels the fp32 pixel pass flagged
  // (shaders/region_layout.h). A module per pass, so each pipeline carries
  // only its own code.
  const Words listed = f64 ? Words(cmr_region_fp64_comp_spv) : Words(cmr_region_fp32_comp_spv);
  const Words tiles = f64 ? Words(cmr_region_tiles_fp64_comp_spv) : Words(cmr_region_tiles_fp32_comp_spv);
  const Words pixels = f64 ? Words(cmr_region_pixels_fp64_comp_spv) : Words(cmr_region_pixels_fp32_comp_spv);
  const ComputePipeline::FollowUp follow[] = {{pixels}, {cmr_region_second_fp64_comp_spv}};
  auto created = key.deep ? ComputePipeline::create(context_, tiles, spec,
                                                    std::span<const ComputePipeline::FollowUp>(follow, cascade ? 2 : 1))
                          : ComputePipeline::create(context_, listed, 0, spec);
  if (!created) return created.error();
  pipelines_.emplace_back(key, created.take());
  pipeline_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  save_pipeline_cache();
  return &pipelines_.back().second;
}

Result<ComputePipeline*> VulkanRegionBackend::prepare(const RegionSetup& s, bool deep) {
  if (options_.precision == RegionPrecision::fp64 && !options_.cascade && !context_.device().float64)
    return Error{Errc::missing_feature, VK_SUCCESS,
                 "device '" + context_.device().name + "' lacks shaderFloat64; use " + field("precision") + " fp32"};
  auto pipeline = pipeline_for(s, deep);
  if (!pipeline) return pipeline.error();
  if (options_.fault == InjectedFault::out_of_memory)
    return Error{Errc::out_of_memory, VK_ERROR_OUT_OF_DEVICE_MEMORY,
                 "vkAllocateMemory failed: VK_ERROR_OUT_OF_DEVICE_MEMORY (injected)"};
  return pipeline;
}

Result<void> VulkanRegionBackend::shade_listed(const RegionSetup& s, const std::vector<std::array<int, 2>>& pixels,
                                               std::vector<uint32_t>& words) {
  auto pipeline = prepare(s, false);
  if (!pipeline) return pipeline.error();
  // The listed pixels in one dispatch (one submission, one readback) per
  // run of them.
  words.clear();
  const std::span<const std::array<int, 2>> all(pixels);
  const std::size_t per_run = options_.pixels_per_run > 0 ? options_.pixels_per_run : kListedPerRun;
  for (std::size_t first = 0; first < pixels.size(); first += per_run) {
    const auto run = all.subspan(first, std::min(per_run, pixels.size() - first));
    const std::vector<std::byte> buffer = detail::pack_region(s, options_.precision, run);
    auto out = pipeline.value()->run(buffer, static_cast<uint32_t>(run.size()));
    if (!out) return out.error();
    if (words.empty()) words = out.take();  // the one run of most frames: no copy
    else words.insert(words.end(), out.value().begin(), out.value().end());
  }
  if (options_.fault == InjectedFault::device_lost)
    return Error{Errc::device_lost, VK_ERROR_DEVICE_LOST, "vkWaitForFences failed: VK_ERROR_DEVICE_LOST (injected)"};
  return {};
}

Result<void> VulkanRegionBackend::shade_whole(const RegionSetup& s, cmr::backend::RegionImage& img) {
  auto pipeline = prepare(s, true);
  if (!pipeline) return pipeline.error();
  const RegionRequest& o = s.options;
  const bool cascade = this->cascade();
  std::vector<std::byte> buffer = detail::pack_region(s, cascade ? RegionPrecision::fp64 : options_.precision, {}, true);
  if (cascade) {
    // Every pair twice: in double, then in float (shaders/region_layout.h).
    const std::vector<std::byte> floats = detail::pack_region(s, RegionPrecision::fp32, {}, true);
    const std::size_t head = std::size_t{HDR_WORDS} * 4, doubles = buffer.size() - head;
    buffer.insert(buffer.end(), floats.begin() + static_cast<std::ptrdiff_t>(head), floats.end());
    const uint32_t base = static_cast<uint32_t>(doubles / 8), one = 1;  // in float pairs
    std::memcpy(buffer.data() + 4 * HDR_DATA_BASE_F32, &base, 4);
    std::memcpy(buffer.data() + 4 * HDR_CASCADE, &one, 4);
  }
  const auto set_header = [&](uint32_t word, std::size_t value) {
    const uint32_t v = static_cast<uint32_t>(value);
    std::memcpy(buffer.data() + 4 * word, &v, 4);
  };
  // One submission (the tile pass, then the pixel pass over the queued
  // tiles) and one readback per run of whole tile rows: the run's label
  // (and depth) plane, the counters, the queue and the flagged pixels
  // (shaders/region_layout.h).
  const std::size_t width = static_cast<std::size_t>(o.width), tiles_x = (width + TILE - 1) / TILE;
  const std::size_t tile_rows = (static_cast<std::size_t>(o.height) + TILE - 1) / TILE;
  const std::size_t per_run = options_.pixels_per_run > 0 ? options_.pixels_per_run : kWholePerRun;
  const std::size_t rows_per_run = std::max<std::size_t>(1, per_run / (TILE * TILE * tiles_x));
  const std::size_t stride = TILE * tiles_x;  // bytes of a plane's row
  const std::size_t listed = options_.flagged_per_run > 0 ? options_.flagged_per_run : kFlaggedListed;
  // Nothing queued, the groups of both follow-ups (0, 1, 1).
  const uint32_t init[OUT_COUNTER_WORDS] = {0, 0, 1, 1, 0, 0, 0, 1, 1, 0, 0, 0};
  std::vector<std::size_t> flagged;
  bool scan = false;  // more flagged than listed: find them in the label map
  frame_ = {};
  for (std::size_t first = 0; first < tile_rows; first += rows_per_run) {
    const std::size_t R = std::min(rows_per_run, tile_rows - first);
    const std::size_t plane_words = R * TILE * stride / 4, planes = o.depth ? 2 : 1;
    const std::size_t counters = planes * plane_words, queue = counters + OUT_COUNTER_WORDS;
    const std::size_t list = queue + tiles_x * R;
    const uint32_t cap = static_cast<uint32_t>(std::min<std::size_t>(listed, R * TILE * stride));
    set_header(HDR_FIRST_TILE_ROW, first);
    set_header(HDR_TILE_ROWS, R);
    set_header(HDR_OUT_COUNTERS, counters);
    set_header(HDR_OUT_QUEUE, queue);
    set_header(HDR_OUT_LIST, list);
    set_header(HDR_LIST_CAP, cap);
    set_header(HDR_OUT_SECOND, list + cap);
    const uint32_t groups[] = {static_cast<uint32_t>(counters + OUT_GROUPS_X),
                               static_cast<uint32_t>(counters + OUT_SECOND_GROUPS_X)};
    // The planes start at 0: the pixel pass ors its pixels' bytes in.
    const ComputePipeline::Chain chain{static_cast<uint32_t>(counters), init,
                                       std::span<const uint32_t>(groups, cascade ? 2 : 1),
                                       static_cast<uint32_t>(counters)};
    auto out = pipeline.value()->run_chain(
        buffer, static_cast<uint32_t>(tiles_x * R), static_cast<uint32_t>(list + (cascade ? 2 : 1) * cap), chain,
        [&](std::span<const std::byte> bytes) {
          const std::size_t row0 = first * TILE, rows = std::min<std::size_t>(R * TILE, o.height - row0);
          for (std::size_t y = 0; y < rows; ++y) {
            std::memcpy(img.labels.data() + (row0 + y) * width, bytes.data() + y * stride, width);
            if (o.depth)
              std::memcpy(img.depth.data() + (row0 + y) * width, bytes.data() + 4 * plane_words + y * stride, width);
          }
          uint32_t c[OUT_COUNTER_WORDS];
          std::memcpy(c, bytes.data() + 4 * counters, sizeof c);
          frame_.tiles += tiles_x * R;
          frame_.tiles_queued += c[OUT_QUEUED];
          frame_.flagged += c[OUT_FLAGGED];
          frame_.second += c[OUT_SECOND];
          if (c[OUT_FLAGGED] > cap) {
            scan = true;
            return;
          }
          for (uint32_t k = 0; k < c[OUT_FLAGGED]; ++k) {
            uint32_t at;
            std::memcpy(&at, bytes.data() + 4 * (list + k), 4);
            flagged.push_back(at);
          }
        });
    if (!out) return out.error();
    const std::vector<double>& passes = pipeline.value()->last_pass_seconds();
    frame_.pass_seconds.resize(passes.size(), 0.0);
    for (std::size_t k = 0; k < passes.size(); ++k) frame_.pass_seconds[k] += passes[k];
  }
  if (options_.fault == InjectedFault::device_lost)
    return Error{Errc::device_lost, VK_ERROR_DEVICE_LOST, "vkWaitForFences failed: VK_ERROR_DEVICE_LOST (injected)"};
  // What the device could not certify, the host decides.
  if (scan) {
    flagged.clear();
    const std::size_t n = img.labels.size();
    const uint8_t* labels = img.labels.data();
    for (const void* at = std::memchr(labels, PACKED_UNCERTAIN, n); at != nullptr;) {
      const std::size_t k = static_cast<std::size_t>(static_cast<const uint8_t*>(at) - labels);
      flagged.push_back(k);
      at = k + 1 < n ? std::memchr(labels + k + 1, PACKED_UNCERTAIN, n - k - 1) : nullptr;
    }
  }
  decide_on_host(s, flagged, img, options_.threads);
  return {};
}

Result<RegionResult> VulkanRegionBackend::try_render(const RegionProblem& problem) {
  const auto t0 = std::chrono::steady_clock::now();
  const double compiled_before = pipeline_seconds_;
  const RegionSetup& s = problem.setup();
  if (share() == DeviceShare::culled) cmr::backend::wake_cull_workers(s, options_.threads);
  cmr::backend::RegionImage img = cmr::backend::blank_image(s);
  if (share() == DeviceShare::culled) {
    const std::vector<std::array<int, 2>> pixels = cmr::backend::region_cull(s, img, kDeviceBlock, options_.threads);
    if (!pixels.empty()) {
      std::vector<uint32_t> words;
      if (auto r = shade_listed(s, pixels, words); !r) return r.error();
      apply_words(s, pixels, words, img, options_.threads);
    }
  } else {
    if (auto r = shade_whole(s, img); !r) return r.error();
  }
  cmr::backend::check_codes(img.labels);  // the device's codes
  RegionResult r = cmr::backend::to_result(std::move(img));
  r.setup_seconds = pipeline_seconds_ - compiled_before;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

RegionResult VulkanRegionBackend::render(const RegionProblem& problem) {
  auto r = try_render(problem);
  if (!r) {
    if (r.error().code == Errc::size_unsupported) throw InputFieldError(r.error().message);
    throw RegionFailure(r.error());
  }
  return r.take();
}

}  // namespace cmr::vk
