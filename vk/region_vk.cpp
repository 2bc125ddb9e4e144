#include "vk/region_vk.hpp"

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include "region_fp32_frag.h"
#include "region_fp64_frag.h"

namespace cmr::vk {
namespace {

// Buffer layout (shaders/region_common.glsl):
//   uint hdr[32]:
//     0 W, 1 H, 2 mode (1 = cmr), 3 split joint (0 = none), 4 depth D,
//     5 entries E, 6 varying joints J, 7 offset of dx per column (W pairs),
//     8 offset of dy per row (H pairs), 9 entries, 10 joints,
//     11/12 flags of the fixed part of parts 0/1, 13 deepest level of the
//     fixed segments, 14 an untouched segment fails at level 0, 15 levels of
//     precomputed pieces L0 (pieces P = 2^(L0+1) - 1), 16 listed pixels in
//     this run, 17 work-area width, 18 offset of the list ((i, j) pairs).
//   REAL2 data[]: pairs; offsets above count pairs. Bounded quantities are
//   (value, error bound); coefficient lists are plain values, two per pair.
//   An entry (cmr::RegionEntry) is (part, classify?), then d+1 triples
//   (B0.x, B0.y, w) with bounds, then for each piece (heap order) and each
//   xi_k 5 pairs (ten coefficients, poly3.hpp order), then for each piece and
//   each nu_k 2 pairs (c0, c1), (c2, 0).
//   A joint is (left entry, right entry), (part, 0).
enum Flag : uint32_t { kInc = 1, kDec = 2, kNone = 4, kUndecided = 8, kUp = 16, kDown = 32, kKpos = 64, kKneg = 128 };

uint32_t flags_of(const SegmentClass& c, Mode mode) {
  uint32_t f = 0;
  switch (c.monotonicity.curvature) {
    case Curvature::increasing: f |= kInc; break;
    case Curvature::decreasing: f |= kDec; break;
    case Curvature::non_monotone: f |= kNone; break;
    case Curvature::undecided: f |= kUndecided; break;
    case Curvature::constant: break;
  }
  if (mode == Mode::cmr) {
    switch (c.inflection.inflection) {
      case Inflection::present: f |= kNone; break;
      case Inflection::undecided: f |= kUndecided; break;
      case Inflection::none: f |= c.inflection.kappa_sign > 0 ? kKpos : kKneg; break;
    }
  }
  return f;
}

class Packer {
 public:
  explicit Packer(RegionPrecision p) : fp32_(p == RegionPrecision::fp32) {}
  uint32_t hdr[32] = {};
  uint32_t size() const { return static_cast<uint32_t>(pairs_.size()); }
  /// A value with an error bound (an exact double when e = 0).
  void bounded(double v, double e = 0) { pairs_.push_back({v, e, false}); }
  void bounded(const Bounded& b) { bounded(b.v, b.e); }
  /// Two plain values (coefficients; their rounding is in the shader's bound).
  void values(double a, double b) { pairs_.push_back({a, b, true}); }

  std::vector<std::byte> bytes() const {
    const std::size_t scalar = fp32_ ? 4 : 8;
    std::vector<std::byte> out(sizeof(hdr) + pairs_.size() * 2 * scalar);
    std::memcpy(out.data(), hdr, sizeof(hdr));
    std::byte* at = out.data() + sizeof(hdr);
    for (const Pair& p : pairs_) {
      if (fp32_) {
        const float v = static_cast<float>(p.a);
        float e = static_cast<float>(p.b);
        if (!p.plain) {
          // Rounding the value to float moves it; the bound absorbs the move
          // and is itself rounded upwards.
          const double grown = p.b + std::fabs(p.a - static_cast<double>(v));
          e = static_cast<float>(grown);
          if (static_cast<double>(e) < grown) e = std::nextafter(e, std::numeric_limits<float>::infinity());
        }
        std::memcpy(at, &v, 4);
        std::memcpy(at + 4, &e, 4);
      } else {
        std::memcpy(at, &p.a, 8);
        std::memcpy(at + 8, &p.b, 8);
      }
      at += 2 * scalar;
    }
    return out;
  }

 private:
  struct Pair {
    double a, b;
    bool plain;
  };
  bool fp32_;
  std::vector<Pair> pairs_;
};

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

std::vector<std::byte> pack_region(const RegionSetup& s, RegionPrecision precision,
                                   std::span<const std::array<int, 2>> pixels, uint32_t area_width) {
  const RegionOptions& o = s.options;
  const int N = s.spline.segment_count();
  const int split = o.split.value_or(0);
  auto part_of = [&](int seg) { return split > 0 && seg >= split ? 1 : 0; };

  Packer p(precision);
  p.hdr[0] = static_cast<uint32_t>(o.width);
  p.hdr[1] = static_cast<uint32_t>(o.height);
  p.hdr[2] = o.mode == Mode::cmr ? 1 : 0;
  p.hdr[3] = static_cast<uint32_t>(split);
  p.hdr[4] = static_cast<uint32_t>(o.max_depth);
  p.hdr[14] = s.fixed_level0_none ? 1 : 0;
  p.hdr[15] = static_cast<uint32_t>(s.piece_levels);
  const int pieces = (2 << s.piece_levels) - 1;

  // dx, dy of every column and row, exactly as cmr::classify_position forms them.
  p.hdr[7] = p.size();
  for (int i = 0; i < o.width; ++i) p.values(pixel_center(*o.view, o.width, o.height, i, 0).x - s.anchor.x, 0);
  p.hdr[8] = p.size();
  for (int j = 0; j < o.height; ++j) p.values(pixel_center(*o.view, o.width, o.height, 0, j).y - s.anchor.y, 0);

  std::vector<bool> in_entry(N, false), touched(N, false);
  p.hdr[5] = static_cast<uint32_t>(s.entries.size());
  p.hdr[9] = p.size();
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
  // Untouched segments and joints whose jump does not vary fold into the
  // parts' flags; varying joints go to the shader.
  uint32_t flags[2] = {0, 0};
  int fixed_depth = 0;
  for (int seg = 0; seg < N; ++seg) {
    if (touched[seg]) continue;
    flags[part_of(seg)] |= flags_of(s.fixed[seg], o.mode);
    fixed_depth = std::max(fixed_depth, s.fixed[seg].monotonicity.depth);
    if (o.mode == Mode::cmr) fixed_depth = std::max(fixed_depth, s.fixed[seg].inflection.depth);
  }
  std::vector<bool> varies(s.joints.size(), false);
  for (const RegionJoint& j : s.varying) varies[j.joint] = true;
  for (std::size_t j = 0; j < s.joints.size(); ++j) {
    const Joint& jt = s.joints[j];
    if (jt.index == split || varies[j]) continue;  // the split joint's jump is free
    if (jt.jump > 0) flags[part_of(jt.index)] |= kUp;
    if (jt.jump < 0) flags[part_of(jt.index)] |= kDown;
  }
  p.hdr[10] = p.size();
  for (const RegionJoint& j : s.varying) {
    p.values(j.left, j.right);
    p.values(j.part, 0);
  }
  p.hdr[6] = static_cast<uint32_t>(s.varying.size());
  p.hdr[16] = static_cast<uint32_t>(pixels.size());
  p.hdr[17] = area_width;
  p.hdr[18] = p.size();
  for (const auto& [i, j] : pixels) p.values(i, j);
  p.hdr[11] = flags[0];
  p.hdr[12] = flags[1];
  p.hdr[13] = static_cast<uint32_t>(fixed_depth);
  return p.bytes();
}

RegionRenderer::RegionRenderer(Context context) : context_(std::move(context)) {}

Result<std::vector<uint32_t>> RegionRenderer::run(const RegionSetup& s, RegionPrecision precision,
                                                  std::span<const std::array<int, 2>> pixels) {
  if (precision == RegionPrecision::fp64 && !context_.device().float64)
    return Error{Errc::missing_feature, VK_SUCCESS,
                 "device '" + context_.device().name + "' lacks shaderFloat64; use --precision fp32"};
  const Key key{s.spline.degree(), s.options.max_depth, precision, s.options.mode == Mode::cmr, !s.varying.empty()};
  FragmentPipeline* pipeline = nullptr;
  for (auto& [k, pl] : pipelines_)
    if (k == key) pipeline = &pl;
  if (!pipeline) {
    const auto t0 = std::chrono::steady_clock::now();
    const uint32_t spec[4] = {static_cast<uint32_t>(key.degree), static_cast<uint32_t>(key.depth), key.cmr ? 1u : 0u,
                              key.joints ? 1u : 0u};
    std::span<const uint32_t> spirv = precision == RegionPrecision::fp64 ? std::span<const uint32_t>(cmr_region_fp64_frag_spv)
                                                                         : std::span<const uint32_t>(cmr_region_fp32_frag_spv);
    auto created = FragmentPipeline::create(context_, spirv, kWorkAreaWidth, kWorkAreaHeight, 0,
                                            FragmentPipeline::kDefaultBandRows, spec);
    if (!created) return created.error();
    pipelines_.emplace_back(key, created.take());
    pipeline = &pipelines_.back().second;
    pipeline_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  std::vector<uint32_t> out;
  out.reserve(pixels.size());
  const std::size_t per_run = std::size_t{kWorkAreaWidth} * kWorkAreaHeight;
  for (std::size_t first = 0; first < pixels.size(); first += per_run) {
    const auto chunk = pixels.subspan(first, std::min(per_run, pixels.size() - first));
    const std::vector<std::byte> buffer = pack_region(s, precision, chunk, kWorkAreaWidth);
    // Shade only the rows the chunk occupies (whole 4-row tiles, see the shader).
    const uint32_t rows = std::min<uint32_t>(
        kWorkAreaHeight, 4 * static_cast<uint32_t>((chunk.size() + 4 * kWorkAreaWidth - 1) / (4 * kWorkAreaWidth)));
    const VkRect2D area{{0, 0}, {kWorkAreaWidth, rows}};
    auto words = pipeline->run(buffer, {}, std::span<const VkRect2D>(&area, 1));
    if (!words) return words.error();
    // Entry k sits in 4x4 tile k / 16 of the area, at (k % 4, k / 4 % 4) inside it.
    for (std::size_t k = 0; k < chunk.size(); ++k) {
      const std::size_t tile = k >> 4, tx = tile % (kWorkAreaWidth / 4), ty = tile / (kWorkAreaWidth / 4);
      const std::size_t x = tx * 4 + (k & 3), y = ty * 4 + ((k >> 2) & 3);
      out.push_back(words.value()[y * kWorkAreaWidth + x]);
    }
  }
  return out;
}

}  // namespace cmr::vk
