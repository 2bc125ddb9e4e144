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
//   The listed pixels (HDR_LIST_OFFSET) are (column, row) pairs (the culled
//   share, region_fp*.comp), or none (the whole share's modules).
//
// Result word of a listed pixel: label code | depth << RESULT_DEPTH_SHIFT,
// or RESULT_UNCERTAIN when the shader could not certify the pixel.
// Every pixel (the whole share): the image is cut into tiles of TILE x TILE
// pixels, TX = ceil(W / TILE) per tile row; a run covers HDR_TILE_ROWS = R
// tile rows from HDR_FIRST_TILE_ROW. Two passes in one submission
// (vk/compute_pipeline.hpp's follow-ups):
// - the tile pass (region_tiles_fp*.comp): invocation t < TX R proves tile t of the run
//   over the box of its pixels' displacements (per tile column and row, (c,
//   r) pairs at HDR_TILE_X_OFFSET / HDR_TILE_Y_OFFSET: the exact
//   displacements lie within c +- r), with HDR_TILE_PROOFS; a proven tile's
//   label fills its bytes of the label plane, any other tile is appended to
//   the queue (OUT_QUEUED, then the queue at HDR_OUT_QUEUE) and adds a
//   group to the follow-up's dispatch (OUT_GROUPS_X..Z), up to 65535;
// - the pixel pass (region_pixels_fp*.comp): workgroup g takes queued tiles
//   g, g + G, ... (G groups), its invocation y TILE + x pixel (x, y) of the
//   tile (TILE x TILE = 64, the group size).
// Output words (the planes cleared to 0 before the passes): the label
// plane, rows of TILE TX bytes (row y of the run at byte y TILE TX), TILE R
// rows; with HDR_DEPTH_PLANE the depth plane of the
// same shape after it (tiles are then not proven: depths are per pixel);
// the counters at HDR_OUT_COUNTERS; the queue; then the pixels the host
// must decide (their label byte is PACKED_UNCERTAIN), as row-major image
// indices, the first HDR_LIST_CAP of OUT_FLAGGED at HDR_OUT_LIST.
// A cascade (HDR_CASCADE; vk::RegionPrecision::cascade) runs both passes in
// float (region_tiles_fp32.comp, region_fp32.comp) and a third in double
// (region_second_fp64.comp): the float pixel pass hands each pixel it cannot
// certify to the second list (its first HDR_LIST_CAP at HDR_OUT_SECOND,
// counted by OUT_SECOND, a group per 64; the rest straight to the host's
// list), and the double pass decides them again, overwriting their label
// (and depth) bytes, and lists for the host what it cannot certify either.
// Its buffer holds every pair twice: in double from data[HDR_DATA_BASE_F64]
// (0), then in float from data[HDR_DATA_BASE_F32] (counted in float pairs);
// the offsets in hdr count pairs from those bases.
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
// 18: unused
CMR_LAYOUT_CONST(HDR_DEPTH_PLANE, 19u)        // every pixel: 1 = the depth plane follows the labels
CMR_LAYOUT_CONST(HDR_FIRST_TILE_ROW, 20u)     // every pixel: this run's first tile row
CMR_LAYOUT_CONST(HDR_TILE_ROWS, 21u)          // every pixel: tile rows in this run
CMR_LAYOUT_CONST(HDR_TILE_X_OFFSET, 22u)      // every pixel: (c, r) per tile column
CMR_LAYOUT_CONST(HDR_TILE_Y_OFFSET, 23u)      // every pixel: (c, r) per tile row of the image
CMR_LAYOUT_CONST(HDR_TILE_PROOFS, 24u)        // every pixel: 1 = the tile pass tries to prove tiles
CMR_LAYOUT_CONST(HDR_OUT_COUNTERS, 25u)       // every pixel: output word of the counters (OUT_*)
CMR_LAYOUT_CONST(HDR_OUT_QUEUE, 26u)          // every pixel: output word of the tile queue
CMR_LAYOUT_CONST(HDR_OUT_LIST, 27u)           // every pixel: output word of the flagged pixels
CMR_LAYOUT_CONST(HDR_LIST_CAP, 28u)           // every pixel: room for flagged pixels
CMR_LAYOUT_CONST(HDR_DATA_BASE_F64, 29u)      // data[] index of the double pairs (0 but in a cascade)
CMR_LAYOUT_CONST(HDR_DATA_BASE_F32, 30u)      // data[] index (in float pairs) of the float pairs
CMR_LAYOUT_CONST(HDR_CASCADE, 31u)            // every pixel: 1 = fp32 passes, then fp64 for what they flag
CMR_LAYOUT_CONST(HDR_OUT_SECOND, 32u)         // cascade: output word of the fp64 pass's list
CMR_LAYOUT_CONST(HDR_WORDS, 40u)              // size of hdr (data[] then starts 16-byte aligned)

// Tiles (every pixel).
CMR_LAYOUT_CONST(TILE, 8u)           // tile side in pixels (TILE x TILE: the pixel pass's group)
CMR_LAYOUT_CONST(OUT_QUEUED, 0u)     // counter: tiles queued for the pixel pass
CMR_LAYOUT_CONST(OUT_GROUPS_X, 1u)   // counters 1-3: the pixel pass's group counts (x, 1, 1)
CMR_LAYOUT_CONST(OUT_FLAGGED, 4u)    // counter: pixels flagged for the host (may exceed HDR_LIST_CAP)
CMR_LAYOUT_CONST(OUT_SECOND, 5u)     // cascade: pixels the fp32 pixel pass hands to the fp64 pass
CMR_LAYOUT_CONST(OUT_SECOND_GROUPS_X, 6u)  // cascade: counters 6-8, the fp64 pass's group counts (x, 1, 1)
CMR_LAYOUT_CONST(OUT_COUNTER_WORDS, 12u)

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
