#include "vk/space_region_vk.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <vector>

#include "shaders/space_region_layout.h"
#include "space_region_fp64_comp.h"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/parallel.hpp"
#include "vk/buffer_packer.hpp"
#include "vk/compute_pipeline.hpp"

namespace cmr::vk {

namespace {

/// Rational curves: the highest degree the device takes (lambda3 has
/// 11n - 17 coefficients, each a bivariate quintic). Degree 7 ran on lavapipe
/// but NVIDIA's driver (580, H200) rejected its pipeline
/// (vkCreateGraphicsPipelines: VK_ERROR_UNKNOWN, when it was a fragment
/// shader); 2..6 ran on both.
constexpr int kMaxRationalDegree = 6;
using namespace layout;

/// The storage buffer of one run of a polynomial curve
/// (shaders/space_region_layout.h): a per column, b per row, the plane, then
/// the segment data `segments` (a joint run: both segments').
std::vector<std::byte> pack(int width, int height, std::uint32_t mode, const std::vector<double>& a,
                            const std::vector<double>& b, const SpacePlane& plane,
                            const std::vector<std::array<double, 2>>& segments) {
  detail::BufferPacker p(SPACE_HDR_WORDS);
  p.hdr[SPACE_HDR_WIDTH] = static_cast<std::uint32_t>(width);
  p.hdr[SPACE_HDR_HEIGHT] = static_cast<std::uint32_t>(height);
  p.hdr[SPACE_HDR_MODE] = mode;
  p.hdr[SPACE_HDR_COLUMN_OFFSET] = p.size();
  for (const double x : a) p.values(x, 0);
  p.hdr[SPACE_HDR_ROW_OFFSET] = p.size();
  for (const double y : b) p.values(y, 0);
  p.hdr[SPACE_HDR_PLANE_OFFSET] = p.size();
  for (const Vec3& v : {plane.origin, plane.u, plane.v})
    for (int c = 0; c < 3; ++c) p.values(v[c], 0);
  p.hdr[SPACE_HDR_DATA_OFFSET] = p.size();
  for (const auto& [v, e] : segments) p.bounded(v, e);
  return p.bytes();
}

/// The storage buffer of a rational run (SPACE_MODE_RATIONAL_*): offsets x
/// per column, y per row, then the polynomials' terms, their degrees from
/// SPACE_HDR_DEGREE on.
std::vector<std::byte> pack_rational(int width, int height, std::uint32_t mode,
                                     const std::vector<std::array<double, 2>>& x,
                                     const std::vector<std::array<double, 2>>& y,
                                     const std::vector<SpaceRegionProblem::PlanePolynomial>& polys) {
  detail::BufferPacker p(SPACE_HDR_WORDS);
  p.hdr[SPACE_HDR_WIDTH] = static_cast<std::uint32_t>(width);
  p.hdr[SPACE_HDR_HEIGHT] = static_cast<std::uint32_t>(height);
  p.hdr[SPACE_HDR_MODE] = mode;
  p.hdr[SPACE_HDR_COLUMN_OFFSET] = p.size();
  for (const auto& [v, e] : x) p.bounded(v, e);
  p.hdr[SPACE_HDR_ROW_OFFSET] = p.size();
  for (const auto& [v, e] : y) p.bounded(v, e);
  p.hdr[SPACE_HDR_DATA_OFFSET] = p.size();
  for (std::size_t k = 0; k < polys.size(); ++k) {
    if (k < SPACE_HDR_DEGREES) p.hdr[SPACE_HDR_DEGREE + k] = static_cast<std::uint32_t>(polys[k].degree);
    for (const auto& [v, e] : polys[k].terms) p.bounded(v, e);
  }
  return p.bytes();
}

/// Pixels per dispatch: the result words stay under the 2^27 bytes of
/// storage buffer every device allows.
constexpr std::size_t kPixelsPerRun = std::size_t{1} << 25;

/// Every pixel's word of one run buffer (row-major), one dispatch per
/// per_run pixels (SPACE_HDR_FIRST_PIXEL, SPACE_HDR_PIXELS).
Result<std::vector<std::uint32_t>> shade(ComputePipeline& pipeline, std::vector<std::byte> buffer, std::size_t pixels,
                                         std::size_t per_run) {
  std::vector<std::uint32_t> words;
  const auto set_header = [&](std::uint32_t word, std::size_t value) {
    const auto v = static_cast<std::uint32_t>(value);
    std::memcpy(buffer.data() + 4 * word, &v, 4);
  };
  for (std::size_t first = 0; first < pixels; first += per_run) {
    const std::size_t count = std::min(per_run, pixels - first);
    set_header(SPACE_HDR_FIRST_PIXEL, first);
    set_header(SPACE_HDR_PIXELS, count);
    auto out = pipeline.run(buffer, static_cast<std::uint32_t>(count));
    if (!out) return out.error();
    if (words.empty()) words = out.take();  // the one run of most frames: no copy
    else words.insert(words.end(), out.value().begin(), out.value().end());
  }
  return words;
}

/// v - base with a bound on its rounding (round to nearest: at most
/// 2^-53 of the exact difference, so below 2^-52 |fl(v - base)|).
std::array<double, 2> offset(double v, double base) {
  const double d = v - base;
  return {d, 0x1p-52 * std::abs(d)};
}

MonotonicityResult decode_segment(std::uint32_t w) {
  static constexpr Curvature kCodes[] = {Curvature::increasing, Curvature::decreasing, Curvature::non_monotone,
                                         Curvature::undecided, Curvature::constant};
  return {kCodes[w & 255u], static_cast<int>(w >> 8)};
}

}  // namespace

Result<RegionResult> render_space_region_vulkan(const SpaceRegionProblem& problem, const SpaceRegionVkOptions& options,
                                                SpaceRegionVkStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  const SpaceRegionRequest& r = problem.request();
  const SpaceSpline& spline = problem.spline();
  const bool rational = spline.is_rational();
  const int max_degree = rational ? kMaxRationalDegree : 7;
  if (spline.degree() < 2 || spline.degree() > max_degree)
    return Error{Errc::size_unsupported, VK_SUCCESS,
                 field("backend") + " vulkan: " + (rational ? "rational " : "") + "space curves of degree 2.." +
                     std::to_string(max_degree) + " only (this one has degree " + std::to_string(spline.degree()) +
                     "; use " + field("backend") + " cpu)"};
  ContextOptions co;
  co.device_name = options.device;
  co.require_float64 = true;
  auto context = Context::create(co);
  if (!context) return context.error();
  const std::uint32_t spec[3] = {static_cast<std::uint32_t>(spline.degree()), static_cast<std::uint32_t>(r.max_depth),
                                 rational ? 1u : 0u};
  auto pipeline = ComputePipeline::create(context.value(), std::span<const std::uint32_t>(cmr_space_region_fp64_comp_spv), 0,
                                          spec);
  if (!pipeline) return pipeline.error();
  const std::size_t pixels = static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height);
  const std::size_t per_run = options.pixels_per_run > 0 ? options.pixels_per_run : kPixelsPerRun;

  // Plane coordinates of the pixel centres, exactly as the CPU forms them.
  std::vector<double> a(static_cast<std::size_t>(r.width)), b(static_cast<std::size_t>(r.height));
  for (int i = 0; i < r.width; ++i) a[static_cast<std::size_t>(i)] = pixel_center(*r.view, r.width, r.height, i, 0).x;
  for (int j = 0; j < r.height; ++j) b[static_cast<std::size_t>(j)] = pixel_center(*r.view, r.width, r.height, 0, j).y;

  // One run per moved segment and per varying joint.
  std::vector<std::vector<std::uint32_t>> seg_words, joint_words;
  const int N = spline.segment_count();
  if (rational) {
    // Each part as polynomials in the offsets from the view's centre (the
    // host's exact derivation, once per render); the device evaluates them.
    const double a0 = 0.5 * r.view->x0 + 0.5 * r.view->x1, b0 = 0.5 * r.view->y0 + 0.5 * r.view->y1;
    std::vector<std::array<double, 2>> x, y;
    for (const double v : a) x.push_back(offset(v, a0));
    for (const double v : b) y.push_back(offset(v, b0));
    for (const int s : problem.moved_segments()) {
      auto words = shade(pipeline.value(),
                         pack_rational(r.width, r.height, SPACE_MODE_RATIONAL_SEGMENT, x, y, problem.rational_lambda3(s, a0, b0)),
                         pixels, per_run);
      if (!words) return words.error();
      seg_words.push_back(std::move(words.value()));
    }
    for (const int j : problem.moved_joints()) {
      const auto p = problem.rational_jump(j, a0, b0);
      const std::vector<SpaceRegionProblem::PlanePolynomial> polys(p.begin(), p.end());
      auto words = shade(pipeline.value(), pack_rational(r.width, r.height, SPACE_MODE_RATIONAL_JOINT, x, y, polys), pixels, per_run);
      if (!words) return words.error();
      joint_words.push_back(std::move(words.value()));
    }
  }
  for (const int s : rational ? std::vector<int>{} : problem.moved_segments()) {
    auto words =
        shade(pipeline.value(), pack(r.width, r.height, SPACE_MODE_SEGMENT, a, b, *r.plane, problem.affine_bezier(s)), pixels, per_run);
    if (!words) return words.error();
    seg_words.push_back(std::move(words.value()));
  }
  for (const int j : rational ? std::vector<int>{} : problem.moved_joints()) {
    std::vector<std::array<double, 2>> both = problem.affine_bezier(j - 1);
    const std::vector<std::array<double, 2>> right = problem.affine_bezier(j % N);
    both.insert(both.end(), right.begin(), right.end());
    auto words = shade(pipeline.value(), pack(r.width, r.height, SPACE_MODE_JOINT, a, b, *r.plane, both), pixels, per_run);
    if (!words) return words.error();
    joint_words.push_back(std::move(words.value()));
  }

  RegionResult out = RegionResult::blank(r.width, r.height, *r.view);
  const std::size_t n = out.size();
  std::vector<std::uint8_t> exact(n, 0), host(n, 0);
  parallel_for(static_cast<std::size_t>(r.height), options.threads, [&](std::size_t j) {
    std::vector<MonotonicityResult> moved(seg_words.size());
    std::vector<int> jumps(joint_words.size());
    for (int i = 0; i < r.width; ++i) {
      const std::size_t idx = j * static_cast<std::size_t>(r.width) + static_cast<std::size_t>(i);
      bool certain = true;
      for (std::size_t s = 0; s < seg_words.size() && certain; ++s) {
        certain = (seg_words[s][idx] & RESULT_UNCERTAIN) == 0;
        if (certain) moved[s] = decode_segment(seg_words[s][idx]);
      }
      for (std::size_t k = 0; k < joint_words.size() && certain; ++k) {
        certain = (joint_words[k][idx] & RESULT_UNCERTAIN) == 0;
        if (certain) jumps[k] = static_cast<int>(joint_words[k][idx]) - 1;
      }
      RegionPixel p;
      if (certain) {
        p = problem.compose(moved, jumps);
      } else {  // the CPU decides: error bounds, then exact
        p = problem.classify(a[static_cast<std::size_t>(i)], b[j]);
        host[idx] = 1;
      }
      out.labels[idx] = p.label;
      out.depth[idx] = p.depth;
      exact[idx] = p.exact ? 1 : 0;
    }
  });
  for (const std::uint8_t e : exact) out.exact_pixels += e;
  if (stats) {
    stats->host_pixels = 0;
    for (const std::uint8_t h : host) stats->host_pixels += h;
    stats->device_pixels = n - stats->host_pixels;
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

RegionResult VulkanSpaceRegionBackend::render(const SpaceRegionProblem& problem) {
  stats_ = {};
  auto rendered = render_space_region_vulkan(problem, options_, &stats_);
  if (!rendered) {
    if (rendered.error().code == Errc::size_unsupported) throw InputFieldError(rendered.error().message);
    throw EnvironmentFieldError(rendered.error().message);
  }
  return rendered.take();
}

}  // namespace cmr::vk
