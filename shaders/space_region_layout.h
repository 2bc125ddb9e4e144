// The space region shader's storage buffer (shaders/space_region_fp64.comp),
// named once for both sides: included by C++ (vk/space_region_vk.cpp packs
// the buffer) and by GLSL (the shader reads it), as region_layout.h is for
// the planar shader, whose result flag (RESULT_UNCERTAIN) it shares.
//
// Buffer: `uint hdr[SPACE_HDR_WORDS]`, then `dvec2 data[]` (value, error
// bound); the offsets in hdr count pairs. What each mode reads: the shader's
// header comment.
#ifndef CMR_SHADERS_SPACE_REGION_LAYOUT_H
#define CMR_SHADERS_SPACE_REGION_LAYOUT_H

#include "region_layout.h"

#ifdef __cplusplus
#include <cstdint>
#define CMR_LAYOUT_CONST(name, value) inline constexpr std::uint32_t name = value;
namespace cmr::vk::layout {
#else
#define CMR_LAYOUT_CONST(name, value) const uint name = value;
#endif

// Header words (indices into hdr).
CMR_LAYOUT_CONST(SPACE_HDR_WIDTH, 0u)         // image width W
CMR_LAYOUT_CONST(SPACE_HDR_HEIGHT, 1u)        // image height H
CMR_LAYOUT_CONST(SPACE_HDR_MODE, 2u)          // SPACE_MODE_*
CMR_LAYOUT_CONST(SPACE_HDR_COLUMN_OFFSET, 3u) // per column: plane coordinate a (modes 0, 1) or offset x (2, 3)
CMR_LAYOUT_CONST(SPACE_HDR_ROW_OFFSET, 4u)    // per row: plane coordinate b (modes 0, 1) or offset y (2, 3)
CMR_LAYOUT_CONST(SPACE_HDR_PLANE_OFFSET, 5u)  // modes 0, 1: the plane O, U, V (nine entries)
CMR_LAYOUT_CONST(SPACE_HDR_DATA_OFFSET, 6u)   // the segment data (0, 1) or the polynomials (2, 3)
CMR_LAYOUT_CONST(SPACE_HDR_DEGREE, 7u)        // modes 2, 3: degrees of the polynomials, three words from here
CMR_LAYOUT_CONST(SPACE_HDR_DEGREES, 3u)       // how many degree words
CMR_LAYOUT_CONST(SPACE_HDR_FIRST_PIXEL, 10u)  // this run's first pixel (row-major)
CMR_LAYOUT_CONST(SPACE_HDR_PIXELS, 11u)       // this run's pixels: result word k is pixel FIRST + k
CMR_LAYOUT_CONST(SPACE_HDR_WORDS, 16u)        // size of hdr

// Modes: what one run judges.
CMR_LAYOUT_CONST(SPACE_MODE_SEGMENT, 0u)           // a moved segment (Algorithm 1 on lambda3)
CMR_LAYOUT_CONST(SPACE_MODE_JOINT, 1u)             // a varying joint's curvature jump
CMR_LAYOUT_CONST(SPACE_MODE_RATIONAL_SEGMENT, 2u)  // a rational curve's segment, from polynomials in (x, y)
CMR_LAYOUT_CONST(SPACE_MODE_RATIONAL_JOINT, 3u)    // a rational curve's joint, from polynomials in (x, y)

#ifdef __cplusplus
}  // namespace cmr::vk::layout
#endif
#undef CMR_LAYOUT_CONST

#endif  // CMR_SHADERS_SPACE_REGION_LAYOUT_H
