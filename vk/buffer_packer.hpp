// Private to cmr_vk: the one packer of the region shaders' storage buffers,
// planar (vk/region_vk.cpp, shaders/region_layout.h) and space
// (vk/space_region_vk.cpp, shaders/space_region_layout.h). A buffer is a
// header of uint words, written through the layout's named fields
// (hdr[HDR_WIDTH], hdr[SPACE_HDR_MODE], ...), then pairs of REAL: double, or
// float for the planar fp32 shader. Not part of the public API.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "numeric/bounded.hpp"
#include "vk/region_vk.hpp"

namespace cmr::vk::detail {

class BufferPacker {
 public:
  /// A header of `header_words` words, all 0 until set.
  explicit BufferPacker(std::uint32_t header_words, RegionPrecision p = RegionPrecision::fp64)
      : hdr(header_words, 0u), fp32_(p == RegionPrecision::fp32) {}
  std::vector<std::uint32_t> hdr;
  /// Pairs so far: the offset (in pairs) of the next one, as the header stores offsets.
  std::uint32_t size() const { return static_cast<std::uint32_t>(pairs_.size()); }
  /// A value with an error bound (an exact double when e = 0).
  void bounded(double v, double e = 0) { pairs_.push_back({v, e, false}); }
  void bounded(const Bounded& b) { bounded(b.v, b.e); }
  /// Two plain values (coefficients; their rounding is in the shader's bound).
  void values(double a, double b) { pairs_.push_back({a, b, true}); }

  std::vector<std::byte> bytes() const {
    const std::size_t scalar = fp32_ ? 4 : 8;
    const std::size_t head = hdr.size() * sizeof(std::uint32_t);
    std::vector<std::byte> out(head + pairs_.size() * 2 * scalar);
    std::memcpy(out.data(), hdr.data(), head);
    std::byte* at = out.data() + head;
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

}  // namespace cmr::vk::detail
