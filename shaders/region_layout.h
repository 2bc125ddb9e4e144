// The region shader's storage buffer and result word, named once for both
// sides: included by C++ (vk/region_vk.cpp packs the buffer, decodes the
// words) and by GLSL (shaders/region_common.glsl reads them). Valid as both
// languages: only integer constants, declared through CMR_LAYOUT_CONST.
//
// Buffer: `uint hdr[HDR_WORDS]`, then `REAL2 data[]` (pairs of REAL; the
// offsets in hdr count pairs). Bounded quantities are (value, error bound);
// coefficient lists are plain values, two per pair.
//   dx per column (HDR_DX_OFFSET, W pairs (dx, 0)), dy per row (HDR_DY_OFFSET,
//   H pairs), exactly as cmr::detail::classify_position forms them.
//   An entry (cmr::detail::RegionEntry, HDR_ENTRY_OFFSET) is (part, classify?),
//   then d+1 triples (B0.x, B0.y, w) with bounds, then for each piece (heap
//   order) and each xi_k 5 pairs (ten coefficients, poly3.hpp order), then for
//   each piece and each nu_k 2 pairs (c0, c1), (c2, 0).
//   Entries and varying joints come in ascending order, so their groups
//   ("part") never decrease.
//   A varying joint (HDR_JOINT_OFFSET) is (left entry, right entry), (part, 0).
//   The groups (HDR_PART_OFFSET, HDR_PARTS pairs) are (flags, 0): FLAG_* of
//   the group's untouched judged segments and non-varying joints.
//   The listed pixels (HDR_LIST_OFFSET) are (column, row) pairs, or none
//   when HDR_EVERY_PIXEL is set (the device shades the whole image).
//
// Result word of a listed pixel: label code | depth << RESULT_DEPTH_SHIFT,
// or RESULT_UNCERTAIN when the shader could not certify the pixel.
// Every pixel (HDR_EVERY_PIXEL): a run covers HDR_LISTED = m pixels from
// HDR_FIRST_PIXEL = f (row-major); invocation k classifies its pixels
// 4k..4k+3 (image pixels f + 4k ..) and writes word k = their label bytes
// (byte q = pixel 4k+q, PACKED_UNCERTAIN where the host must decide) and,
// with HDR_DEPTH_PLANE, word K + k = their depth bytes, K = ceil(m / 4): the
// words read as bytes are that stretch of the label map (and depth map) as
// the host stores it.
#ifndef CMR_SHADERS_REGION_LAYOUT_H
#define CMR_SHADERS_REGION_LAYOUT_H

#ifdef __cplusplus
#include <cstdint>
#define CMR_LAYOUT_CONST(name, value) inline constexpr std::uint32_t name = value;
namespace cmr::vk::layout {
#else
#define CMR_LAYOUT_CONST(name, value) const uint name = value;
#endif

// Header words (indices into hdr).
CMR_LAYOUT_CONST(HDR_WIDTH, 0u)               // image width W
CMR_LAYOUT_CONST(HDR_HEIGHT, 1u)              // image height H
CMR_LAYOUT_CONST(HDR_MODE, 2u)                // 1 = cmr, 0 = cmrwi
CMR_LAYOUT_CONST(HDR_LABELS, 3u)              // LABELS_*: which labels the pixels get
CMR_LAYOUT_CONST(HDR_DEPTH, 4u)               // maximum depth D
CMR_LAYOUT_CONST(HDR_ENTRIES, 5u)             // number of entries E
CMR_LAYOUT_CONST(HDR_JOINTS, 6u)              // number of varying joints J
CMR_LAYOUT_CONST(HDR_DX_OFFSET, 7u)           // dx per column
CMR_LAYOUT_CONST(HDR_DY_OFFSET, 8u)           // dy per row
CMR_LAYOUT_CONST(HDR_ENTRY_OFFSET, 9u)        // the entries
CMR_LAYOUT_CONST(HDR_JOINT_OFFSET, 10u)       // the varying joints
CMR_LAYOUT_CONST(HDR_PARTS, 11u)              // number of groups of judged segments (1 + cut joints)
CMR_LAYOUT_CONST(HDR_PART_OFFSET, 12u)        // the groups' fixed flags
CMR_LAYOUT_CONST(HDR_FIXED_DEPTH, 13u)        // deepest level of the fixed segments
CMR_LAYOUT_CONST(HDR_FIXED_LEVEL0_NONE, 14u)  // 1: an untouched segment fails at level 0
CMR_LAYOUT_CONST(HDR_PIECE_LEVELS, 15u)       // L0: precomputed pieces P = 2^(L0+1) - 1
CMR_LAYOUT_CONST(HDR_LISTED, 16u)             // listed pixels in this run
CMR_LAYOUT_CONST(HDR_LIST_OFFSET, 17u)        // the listed pixels
CMR_LAYOUT_CONST(HDR_EVERY_PIXEL, 18u)        // 1: no list, every pixel, packed (below)
CMR_LAYOUT_CONST(HDR_DEPTH_PLANE, 19u)        // every pixel: 1 = the depth plane follows the labels
CMR_LAYOUT_CONST(HDR_FIRST_PIXEL, 20u)        // every pixel: this run's pixels start here (row-major)
CMR_LAYOUT_CONST(HDR_WORDS, 32u)              // size of hdr

// Label kinds (cmr::backend::Labels).
CMR_LAYOUT_CONST(LABELS_PLAIN, 0u)        // Direction: one group
CMR_LAYOUT_CONST(LABELS_SPLIT, 1u)        // Split: two groups
CMR_LAYOUT_CONST(LABELS_ALTERNATING, 2u)  // Alternation: any number of groups
CMR_LAYOUT_CONST(LABELS_EACH_PIECE, 3u)   // EachPiece: any number of groups, each on its own

// Flags of a part (segments' verdicts and joints' jumps folded together).
CMR_LAYOUT_CONST(FLAG_INC, 1u)        // some segment increasing
CMR_LAYOUT_CONST(FLAG_DEC, 2u)        // some segment decreasing
CMR_LAYOUT_CONST(FLAG_NONE, 4u)       // some segment not monotone (or, cmr, an inflection)
CMR_LAYOUT_CONST(FLAG_UNDECIDED, 8u)  // some segment undecided at depth D
CMR_LAYOUT_CONST(FLAG_UP, 16u)        // some joint's curvature jumps up
CMR_LAYOUT_CONST(FLAG_DOWN, 32u)      // some joint's curvature jumps down
CMR_LAYOUT_CONST(FLAG_KPOS, 64u)      // cmr: some segment without inflection, kappa > 0
CMR_LAYOUT_CONST(FLAG_KNEG, 128u)     // cmr: some segment without inflection, kappa < 0

// Result word.
CMR_LAYOUT_CONST(RESULT_LABEL_MASK, 255u)   // the label code (cmr::code)
CMR_LAYOUT_CONST(RESULT_DEPTH_SHIFT, 8u)    // the decision level, 8 bits
CMR_LAYOUT_CONST(RESULT_UNCERTAIN, 65536u)  // not certified: the host decides
CMR_LAYOUT_CONST(PACKED_UNCERTAIN, 255u)    // a packed label byte the host decides (no label code is 255)

#ifdef __cplusplus
}  // namespace cmr::vk::layout
#endif
#undef CMR_LAYOUT_CONST

#endif  // CMR_SHADERS_REGION_LAYOUT_H
