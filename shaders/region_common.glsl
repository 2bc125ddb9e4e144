// Curvature monotonicity region, one pixel per invocation: the GPU mirror of
// cmr::classify_position (region/region.cpp), with the same certified
// arithmetic as cmr::Bounded (numeric/bounded.hpp). Every quantity is a
// pair (value, bound on |exact - value|); a sign is certain when
// |value| > bound. A pixel whose deciding signs are not all certain is
// flagged, and the host recomputes it exactly, so labels never depend on how
// this device rounds.
//
// Included by one module per pass (main, at the end): region_fp*.comp (the
// culled share's listed pixels), region_tiles_fp*.comp, region_pixels_fp*.comp
// and region_second_fp64.comp (the whole share's passes: CMR_TILE_PASS,
// CMR_PIXEL_PASS, CMR_SECOND_PASS), and the window's region_present_fp*.frag
// (CMR_REGION_PRESENT). They define REAL, REAL2, K_DATA_BASE, K_ROUND (twice
// the unit roundoff) and K_TINY (absolute slack for underflow, also covering
// flush-to-zero).
//
// Buffer layout and result word: shaders/region_layout.h (shared with the
// C++ side, vk/region_vk.cpp, which packs the buffer).
#include "region_layout.h"

// The whole share's passes (the device halves deep pieces there: DEEP).
#if defined(CMR_TILE_PASS) || defined(CMR_PIXEL_PASS) || defined(CMR_SECOND_PASS)
#define CMR_WHOLE
#endif

layout(constant_id = 0) const int DEG = 3;    // degree n of every segment
layout(constant_id = 1) const int MAXD = 12;  // maximum subdivision depth D
// Specialised away when unused: a SIMD executor such as llvmpipe runs every
// branch under a mask, so code that cannot run must not be in the shader.
layout(constant_id = 2) const bool CMR_MODE = false;  // also run Algorithm 2 (CMR)
layout(constant_id = 3) const bool JOINTS = false;    // some joint's curvature jump varies
// 1: a rational spline (bezierize/rational_lambda.hpp): xi holds lambda's
// 8n-11 coefficients and nu D's 3n-5; the entries' points are homogeneous,
// so joint jumps are left to the host (SIGN_UNKNOWN).
layout(constant_id = 4) const int RATIONAL = 0;
// true: pieces below the precomputed levels are halved here (load_deep)
// rather than left to the host; off where private arrays are costly (a
// SIMD executor such as llvmpipe keeps one per lane even where unused).
layout(constant_id = 5) const bool DEEP = false;
// Tests only (vk::VulkanRegionOptions::weaken_bound_bits): the polynomial
// evaluation bound divided by 2^WEAKEN, a bound too small on purpose, so a
// test can show that a weakened bound gives labels the exact path refutes.
layout(constant_id = 6) const int WEAKEN = 0;
const int NXI = 4 * DEG - 6 + RATIONAL * (4 * DEG - 5);  // coefficients of lambda
const int NNU = 2 * DEG - 3 + RATIONAL * (DEG - 2);      // coefficients of eta (D)

layout(std430, set = 0, binding = 0) readonly buffer RegionData {
  uint hdr[HDR_WORDS];
  REAL2 data[];
};
// Pair i of this module's precision: a cascade's buffer holds the pairs in
// double and then in float (shaders/region_layout.h, HDR_DATA_BASE_*); the
// includer names its base word K_DATA_BASE.
#define DATA(i) data[hdr[K_DATA_BASE] + (i)]

#ifndef CMR_REGION_PRESENT  // region_present.glsl has its own output and main
// One invocation per listed pixel, tile or tile row (vk/compute_pipeline.hpp's
// interface). Not writeonly: the tile queue's counters are atomics.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 1) buffer RegionResult {
  uint result[];
};
#endif

#include "piece_rules.glsl"

#include "bounded.glsl"
REAL2 b_int(int n) { return REAL2(REAL(n), REAL(0)); }

// ---------------------------------------------------------------------------
// Per pixel. Each touched segment's xi_k and nu_k are polynomials in the
// displacement (dx, dy) = p - P_k with coefficients the host computed exactly
// and rounded (cmr::RegionEntry); evaluating one costs ten products, and its
// error bound is K_POLY units of roundoff times sum |c_m| |mu_m| (the
// count below).

// The count, in units u of the shader's arithmetic (K_ROUND = 2u), for
// fp64 and fp32 alike (region/region_setup.hpp derives it for the host):
// dx carries one rounding, the monomials two more, the coefficient one, its
// product one, the sum of ten products nine: 16 u, and 24 leave slack for
// the bound's own rounding. In fp32 (region_fp32.comp) dx and the
// coefficients are doubles the packer rounds to float: fl32(fl64(x)) is
// within (2^-53 + 2^-24 (1 + 2^-53)) |x| < 1.0000001 u |x| of x, still one
// unit each. Coefficients that would be subnormal or overflow in float
// arrive as NaN (region_vk.cpp, for_device), which no sign test accepts;
// K_TINY covers the underflow of products and the flush of denormals. A
// bound made 2^24 times smaller is caught by the tests
// (CertifyBound.AWeakenedFp32BoundGivesLabelsTheExactPathRefutes).
const REAL K_POLY = REAL(24) * REAL(0.5) * K_ROUND;

REAL mono[10];
REAL amono[10];

void set_monomials(REAL dx, REAL dy) {
  REAL x2 = dx * dx, xy = dx * dy, y2 = dy * dy;
  mono[0] = REAL(1); mono[1] = dx; mono[2] = dy; mono[3] = x2; mono[4] = xy; mono[5] = y2;
  mono[6] = x2 * dx; mono[7] = x2 * dy; mono[8] = y2 * dx; mono[9] = y2 * dy;
  for (int m = 0; m < 10; ++m) amono[m] = abs(mono[m]);
}

// The bound on |exact - computed| of one coefficient polynomial at this
// pixel, mag = sum |c_m| |mu_m| (the terms' magnitudes).
REAL poly_bound(REAL mag) {
  REAL bound = K_POLY * mag + REAL(16) * K_TINY;
  if (WEAKEN > 0) bound = ldexp(bound, -WEAKEN);
  return bound;
}

uint pieces() { return (2u << hdr[HDR_PIECE_LEVELS]) - 1u; }
uint entry_at(uint e) { return hdr[HDR_ENTRY_OFFSET] + e * (uint(1 + 3 * (DEG + 1)) + pieces() * uint(5 * NXI + 2 * NNU)); }

// Coefficient k of piece p (heap order) of xi for entry e at this pixel, with its error bound.
// A polynomial whose coefficients are all zero is exactly zero (the host
// guarantees it), so its sign is certain.
#ifdef CMR_TILE_PASS
REAL2 xi_box(uint at);  // over the tile's box (region_tiles.glsl)
REAL2 nu_box(uint at);
#endif

REAL2 xi_at(uint e, int p, int k) {
  uint at = entry_at(e) + uint(1 + 3 * (DEG + 1)) + uint(5 * (p * NXI + k));
#ifdef CMR_TILE_PASS
  return xi_box(at);
#endif
  REAL v = REAL(0), mag = REAL(0);
  bool zero = true;
  for (int h = 0; h < 5; ++h) {
    REAL2 c = DATA(at + uint(h));
    v += c.x * mono[2 * h] + c.y * mono[2 * h + 1];
    mag += abs(c.x) * amono[2 * h] + abs(c.y) * amono[2 * h + 1];
    zero = zero && c.x == REAL(0) && c.y == REAL(0);
  }
  if (zero) return REAL2(0);
  return REAL2(v, poly_bound(mag));
}

REAL2 nu_at(uint e, int p, int k) {
  uint at = entry_at(e) + uint(1 + 3 * (DEG + 1)) + pieces() * uint(5 * NXI) + uint(2 * (p * NNU + k));
#ifdef CMR_TILE_PASS
  return nu_box(at);
#endif
  REAL2 c01 = DATA(at), c2 = DATA(at + 1u);
  REAL v = c01.x + c01.y * mono[1] + c2.x * mono[2];
  REAL mag = abs(c01.x) + abs(c01.y) * amono[1] + abs(c2.x) * amono[2];
  if (c01.x == REAL(0) && c01.y == REAL(0) && c2.x == REAL(0)) return REAL2(0);
  return REAL2(v, poly_bound(mag));
}

// Depth-first Algorithms 1 and 2 on the piece polynomials (region/region.cpp,
// lazy_algorithm1/2): ends first, inner coefficients until both signs appear.
// Pieces below the precomputed levels are left to the host (P_DEEP) unless
// DEEP (the whole share's modules only), when load_deep makes their
// coefficients here.
const int P_DEEP = 8;

#ifdef CMR_WHOLE
// The coefficients of the piece below the precomputed levels being decided
// (DEEP only; piece index -1 reads them).
REAL2 deep_c[NXI];
#endif

REAL2 coeff_at(uint e, bool eta, int p, int k) {
#ifdef CMR_WHOLE
  if (DEEP && p < 0) return deep_c[k];
#endif
  return eta ? nu_at(e, p, k) : xi_at(e, p, k);
}

#ifdef CMR_WHOLE
// (c_a + c_b) / 2 with its bound; an exact zero stays exact (cmr::Bounded::half).
REAL2 deep_mid(REAL2 a, REAL2 b) {
  REAL2 s = b_add(a, b);
  return s == REAL2(0) ? s : b_half(s);
}

// Piece j of `level` (> levels, the deepest precomputed level) into deep_c:
// its ancestor at `levels` evaluated at this pixel, then halved at t = 1/2
// (de Casteljau) level by level towards it, keeping the left or the right
// half as the path's bits say. Every step is certified arithmetic (b_add,
// b_half), so each coefficient keeps a bound on its distance from the exact
// coefficient of the exact piece, as cmr's Bounded halving does on the host
// (LazyPieces, region/kernel.hpp); a sign the bound does not decide sends
// the pixel to the host as before. O((level - levels) n^2) per piece,
// n = NXI or NNU.
void load_deep(uint e, bool eta, int level, int j, int levels) {
  int n1 = eta ? NNU : NXI;
  int r = level - levels;
  int root = (1 << levels) - 1 + (j >> r);
  for (int k = 0; k < n1; ++k) deep_c[k] = eta ? nu_at(e, root, k) : xi_at(e, root, k);
  for (int b = r - 1; b >= 0; --b) {
    if (((j >> b) & 1) != 0) {  // the right half: c_i <- (c_i + c_{i+1}) / 2, ascending
      for (int t = 1; t < n1; ++t)
        for (int i = 0; i + t < n1; ++i) deep_c[i] = deep_mid(deep_c[i], deep_c[i + 1]);
    } else {  // the left half: c_i <- (c_{i-1} + c_i) / 2, descending
      for (int t = 1; t < n1; ++t)
        for (int i = n1 - 1; i >= t; --i) deep_c[i] = deep_mid(deep_c[i - 1], deep_c[i]);
    }
  }
}
#endif  // CMR_WHOLE

#ifdef CMR_TILE_PASS
#include "region_tiles.glsl"
#endif

// Returns P_UNCERTAIN or P_DEEP when the host must decide; otherwise 0 and
// the outcome (curvature: 0 inc, 1 dec, 2 non-monotone, 3 undecided,
// 4 constant; inflection: 0 none, 1 present, 2 undecided).
int traverse(uint e, bool eta, int maxd, out int outcome, out int depth, out int kappa_sign) {
  // Stackless depth-first order: after a leaf, climb while on a right child,
  // then step to the right sibling (no arrays: private arrays are costly on
  // SIMD executors even where unused).
  int levels = int(hdr[HDR_PIECE_LEVELS]);
  kappa_sign = SIGN_UNKNOWN;  // the root's coefficient 0, read by its decide_piece
  int level = 0, j = 0;
  bool inc = false, dec = false, undecided = false;
  int deepest = 0;
  outcome = -1;
  depth = 0;
  for (;;) {
    int piece = (1 << level) - 1 + j;
    if (level > levels) {
#ifdef CMR_WHOLE
      if (!DEEP) return P_DEEP;
      load_deep(e, eta, level, j, levels);
#else
      return P_DEEP;  // the culled share and the window leave deep pieces to the host
#endif
      piece = -1;
    }
    int first;
    int p = decide_piece(e, eta, piece, eta ? NNU : NXI, first);
    if (level == 0) kappa_sign = first;
    if (p == P_UNCERTAIN) return P_UNCERTAIN;
    if (p == P_SPLIT && level < maxd) {
      ++level;
      j *= 2;
      continue;
    }
    if (p == P_ZERO) { outcome = 4; depth = level; break; }
    if (p == P_NONMONO) { outcome = 2; depth = level; break; }
    if (p == P_INFL) { outcome = 1; depth = level; break; }
    if (p == P_INC) inc = true;
    else if (p == P_DEC) dec = true;
    else if (p != P_NOINFL) undecided = true;
    deepest = max(deepest, level);
    if (inc && dec) { outcome = 2; depth = level; break; }
    while (level > 0 && (j & 1) == 1) { --level; j >>= 1; }
    if (level == 0) break;
    ++j;
  }
  if (outcome < 0) {
    if (undecided) { outcome = eta ? 2 : 3; depth = maxd; }
    else { outcome = eta ? 0 : (inc ? 0 : 1); depth = deepest; }
  }
  return 0;
}

// Bezier point i of entry e moved by (dx, dy), with bounds.
void moved_point(uint e, int i, REAL2 dx, REAL2 dy, out REAL2 x, out REAL2 y) {
  uint at = entry_at(e) + 1u + uint(3 * i);
  REAL2 w = DATA(at + 2u);
  x = b_add(DATA(at), b_mul(w, dx));
  y = b_add(DATA(at + 1u), b_mul(w, dy));
}

REAL2 det2(REAL2 ax_, REAL2 ay_, REAL2 bx_, REAL2 by_) { return b_sub(b_mul(ax_, by_), b_mul(ay_, bx_)); }
REAL2 dot2(REAL2 ax_, REAL2 ay_, REAL2 bx_, REAL2 by_) { return b_add(b_mul(ax_, bx_), b_mul(ay_, by_)); }

// Sign of kappa_right - kappa_left at a joint from the end legs of its two
// segments (cmr::jump_sign); SIGN_UNKNOWN when not certain. Scalars only.
int jump_sign(uint le, uint re, REAL2 bdx, REAL2 bdy) {
  if (RATIONAL != 0) return SIGN_UNKNOWN;  // the host decides (cmr::jump_sign_homogeneous)
  REAL2 l0x, l0y, l1x, l1y, l2x, l2y, r0x, r0y, r1x, r1y, r2x, r2y;
  moved_point(le, DEG, bdx, bdy, l0x, l0y);  // the left segment read from its end
  moved_point(le, DEG - 1, bdx, bdy, l1x, l1y);
  moved_point(le, DEG - 2, bdx, bdy, l2x, l2y);
  moved_point(re, 0, bdx, bdy, r0x, r0y);
  moved_point(re, 1, bdx, bdy, r1x, r1y);
  moved_point(re, 2, bdx, bdy, r2x, r2y);
  REAL2 lax = b_sub(l1x, l0x), lay = b_sub(l1y, l0y);
  REAL2 lbx = b_sub(l2x, l1x), lby = b_sub(l2y, l1y);
  REAL2 rax = b_sub(r1x, r0x), ray = b_sub(r1y, r0y);
  REAL2 rbx = b_sub(r2x, r1x), rby = b_sub(r2y, r1y);
  REAL2 AL = b_sub(b_int(0), det2(lax, lay, lbx, lby));
  REAL2 GL = dot2(lax, lay, lax, lay);
  REAL2 AR = det2(rax, ray, rbx, rby);
  REAL2 GR = dot2(rax, ray, rax, ray);
  if (b_sign(GL) == SIGN_UNKNOWN || b_sign(GR) == SIGN_UNKNOWN) return SIGN_UNKNOWN;
  int sx = b_sign(AR), sy = b_sign(AL);
  if (sx == SIGN_UNKNOWN || sy == SIGN_UNKNOWN) return SIGN_UNKNOWN;
  if (sx != sy) return sx > sy ? 1 : -1;
  REAL2 x2 = b_mul(b_mul(b_mul(b_mul(AR, AR), GL), GL), GL);
  REAL2 y2 = b_mul(b_mul(b_mul(b_mul(AL, AL), GR), GR), GR);
  int c = b_sign(b_sub(x2, y2));
  if (c == SIGN_UNKNOWN) return SIGN_UNKNOWN;
  return sx > 0 ? c : -c;
}

int direction_of(uint f, bool cmr) {  // 0 inc, 1 dec, 2 none, 3 undecided (cmr::part_verdict)
  bool none = (f & FLAG_NONE) != 0u || ((f & FLAG_INC) != 0u && (f & FLAG_DEC) != 0u) ||
              (cmr && (f & FLAG_KPOS) != 0u && (f & FLAG_KNEG) != 0u);
  if (none) return 2;
  if (((f & FLAG_UP) != 0u && (f & FLAG_DEC) != 0u) || ((f & FLAG_DOWN) != 0u && (f & FLAG_INC) != 0u)) return 2;
  if ((f & FLAG_UP) != 0u && (f & FLAG_DOWN) != 0u) return 2;
  if ((f & FLAG_UNDECIDED) != 0u) return 3;
  if ((f & FLAG_DEC) != 0u || (f & FLAG_DOWN) != 0u) return 1;
  return 0;
}

const uint UNCERTAIN = RESULT_UNCERTAIN;
const uint UNDECIDED_YET = 0xffffffffu;

// Level 0 (cmr::classify_position): a segment whose end coefficients prove
// non-monotonicity (or, for CMR, an inflection) decides the pixel.
uint level0(bool cmr) {
  uint E = hdr[HDR_ENTRIES];
  bool uncertain = false;
  for (uint e = 0u; e < E; ++e) {
    if (DATA(entry_at(e)).y == REAL(0)) continue;  // a neighbour only
    // cmr::level0_fails: certain failures decide; unknown ones wait for the host.
    // Each polynomial read at one call site (decide_piece says why).
    for (int eta = 0; eta < (cmr ? 2 : 1); ++eta) {
      int n1 = eta == 1 ? NNU : NXI, ends[2];
      for (int t = 0; t < 2; ++t) ends[t] = b_sign(coeff_at(e, eta == 1, 0, t == 0 ? 0 : n1 - 1));
      int m = eta == 1 ? ends_touch(ends[0], ends[1]) : ends_opposite(ends[0], ends[1]);
      if (m == T_YES) return 0u;
      uncertain = uncertain || m == T_UNKNOWN;
    }
  }
  return uncertain ? UNCERTAIN : UNDECIDED_YET;
}

// Every touched segment through Algorithms 1 (and 2), the varying joints,
// and the verdict (cmr::detail::verdict in region/region.cpp): each group
// of judged segments (cmr::part_verdict), then the label of the groups
// (one group: its direction; two with a split: cmr::combine_split; any
// number: cmr::alternation_verdict, or each on its own:
// cmr::each_piece_verdict). Entries and joints come in ascending
// group order, so the groups are walked once with two cursors (no arrays).
// A pixel's displacement fl(p - P_k) as a bounded value (one rounding).
REAL2 pixel_displacement(REAL d) { return REAL2(d, K_ROUND * abs(d)); }

// In the tile pass each segment's traversal runs over the box (bdx, bdy:
// the tile's displacements) and a segment that fails there decides the
// label (block.cpp, classify_box_labels).
uint full(bool cmr, REAL2 bdx, REAL2 bdy) {
  uint kind = hdr[HDR_LABELS];
  int maxd = int(hdr[HDR_DEPTH]);
  uint E = hdr[HDR_ENTRIES];
  uint J = JOINTS ? hdr[HDR_JOINTS] : 0u;
  uint P = hdr[HDR_PARTS];
  int depth = int(hdr[HDR_FIXED_DEPTH]);
  uint e = 0u, j = 0u;
  int first = 0, second = 0, prev = 0;  // directions of groups 0, 1 and the one before
  bool any_none = false, any_undecided = false, same_way = false;
  for (uint part = 0u; part < P; ++part) {
    uint flags = uint(DATA(hdr[HDR_PART_OFFSET] + part).x);
    for (; e < E && uint(DATA(entry_at(e)).x) == part; ++e) {
      if (DATA(entry_at(e)).y == REAL(0)) continue;  // a neighbour only
      // Algorithm 1, then (CMR) Algorithm 2: each traversal at one call
      // site (decide_piece says why).
      for (int a = 0; a < (cmr ? 2 : 1); ++a) {
        const bool eta = a == 1;
#ifdef CMR_TILE_PASS
        int o = box_traverse(e, eta, maxd);  // eta: positive is no inflection, kappa > 0
        if (o >= 2) return o == 2 ? 0u : UNCERTAIN;
        flags |= eta ? (o == 0 ? FLAG_KPOS : FLAG_KNEG) : (o == 0 ? FLAG_INC : FLAG_DEC);
#else
        int outcome, d, ks;
        if (traverse(e, eta, maxd, outcome, d, ks) != 0) return UNCERTAIN;
        depth = max(depth, d);
        if (!eta) {
          if (outcome == 0) flags |= FLAG_INC;
          else if (outcome == 1) flags |= FLAG_DEC;
          else if (outcome == 2) flags |= FLAG_NONE;
          else if (outcome == 3) flags |= FLAG_UNDECIDED;
        } else {
          if (outcome == 1) flags |= FLAG_NONE;
          else if (outcome == 2) flags |= FLAG_UNDECIDED;
          else flags |= ks > 0 ? FLAG_KPOS : FLAG_KNEG;
        }
#endif
      }
    }
    for (; j < J && uint(DATA(hdr[HDR_JOINT_OFFSET] + 2u * j + 1u).x) == part; ++j) {
      REAL2 ends = DATA(hdr[HDR_JOINT_OFFSET] + 2u * j);
      int s = jump_sign(uint(ends.x), uint(ends.y), bdx, bdy);
      if (s == SIGN_UNKNOWN) return UNCERTAIN;
      flags |= s > 0 ? FLAG_UP : (s < 0 ? FLAG_DOWN : 0u);
    }
    int dir = direction_of(flags, cmr);
    if (part == 0u) first = dir;
    if (part == 1u) second = dir;
    any_none = any_none || dir == 2;
    any_undecided = any_undecided || dir == 3;
    same_way = same_way || (part > 0u && dir == prev && dir < 2);
    prev = dir;
  }
  uint label;
  if (kind == LABELS_PLAIN) {
    label = first == 0 ? 1u : (first == 1 ? 2u : (first == 3 ? 3u : 0u));
  } else if (kind == LABELS_SPLIT) {
    if (first == 2 || second == 2) label = 0u;
    else if (first == 3 || second == 3) label = 5u;
    else label = 1u + uint(first) * 2u + uint(second);  // inc-inc 1, inc-dec 2, dec-inc 3, dec-dec 4
  } else if (kind == LABELS_EACH_PIECE) {
    // fail 0, each-monotone 1, undecided 2 (cmr::EachPiece)
    label = any_none ? 0u : (any_undecided ? 2u : 1u);
  } else {
    // fail 0, inc-first 1, dec-first 2, undecided 3 (cmr::Alternation)
    if (any_none || same_way) label = 0u;
    else if (any_undecided) label = 3u;
    else label = first == 0 ? 1u : 2u;
  }
  return label | (uint(depth) << RESULT_DEPTH_SHIFT);
}

#ifndef CMR_REGION_PRESENT
// The result word of pixel (pi, pj) (shaders/region_layout.h).
uint classify_pixel(int pi, int pj) {
  const bool cmr = CMR_MODE;
  // dx = fl(p - P_k), computed by the host with cmr::pixel_center.
  REAL dx = DATA(hdr[HDR_DX_OFFSET] + uint(pi)).x, dy = DATA(hdr[HDR_DY_OFFSET] + uint(pj)).x;
  set_monomials(dx, dy);
  // Pixels decided at level 0 as not monotone get 0 (label 0, depth 0).
  if (hdr[HDR_FIXED_LEVEL0_NONE] != 0u) return 0u;  // an untouched segment fails at level 0
  uint r = level0(cmr);
  if (r == UNDECIDED_YET) r = full(cmr, pixel_displacement(dx), pixel_displacement(dy));
  return r;
}

#ifdef CMR_TILE_PASS
// The label of every pixel of a tile whose displacements lie in bx.x +- bx.y,
// by.x +- by.y, or RESULT_UNCERTAIN.
uint classify_tile(REAL2 bx, REAL2 by) {
  const bool cmr = CMR_MODE;
  if (hdr[HDR_FIXED_LEVEL0_NONE] != 0u) return 0u;
  set_box(bx.x, bx.y, by.x, by.y);
  uint r = level0(cmr);
  if (r == UNDECIDED_YET) r = full(cmr, bx, by);
  return r;
}
#endif

#if defined(CMR_PIXEL_PASS) || defined(CMR_SECOND_PASS)
// Pixel k (row-major in the image) to the host's list: its first `cap`
// entries; the host scans the label map for the rest.
void to_host(uint k, uint counters, uint list, uint cap) {
  const uint f = atomicAdd(result[counters + OUT_FLAGGED], 1u);
  if (f < cap) result[list + f] = k;
}
#endif

void main() {
  const uint at = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  // One pass per module, so that each pipeline inlines classify_pixel once
  // (the culled share's pipeline had carried the whole share's pixel pass
  // too: lavapipe's one-shot `cmr region` compiled it, 50 ms).
#ifdef CMR_WHOLE
  // Every pixel, by tiles (shaders/region_layout.h).
  const uint w = hdr[HDR_WIDTH], tiles_x = (w + TILE - 1u) / TILE, stride = tiles_x * TILE / 4u;
  const uint counters = hdr[HDR_OUT_COUNTERS], queue = hdr[HDR_OUT_QUEUE];
  const uint list = hdr[HDR_OUT_LIST], cap = hdr[HDR_LIST_CAP];
#endif
#if defined(CMR_TILE_PASS)
  // The tile pass: tile `at` of the run.
  if (at >= tiles_x * hdr[HDR_TILE_ROWS]) return;
  const uint tx = at % tiles_x, tr = at / tiles_x;
  uint r = RESULT_UNCERTAIN;
  if (hdr[HDR_TILE_PROOFS] != 0u)
    r = classify_tile(DATA(hdr[HDR_TILE_X_OFFSET] + tx), DATA(hdr[HDR_TILE_Y_OFFSET] + hdr[HDR_FIRST_TILE_ROW] + tr));
  if ((r & RESULT_UNCERTAIN) == 0u) {  // proven: the tile's bytes all get its label
    const uint word = (r & RESULT_LABEL_MASK) * 0x01010101u;
    for (uint y = 0u; y < TILE; ++y)
      for (uint k = 0u; k < TILE / 4u; ++k) result[(tr * TILE + y) * stride + tx * (TILE / 4u) + k] = word;
    return;
  }
  const uint q = atomicAdd(result[counters + OUT_QUEUED], 1u);
  result[queue + q] = at;
  if (q < 65535u) atomicAdd(result[counters + OUT_GROUPS_X], 1u);  // a group per tile, as many as a dispatch holds
  return;
#elif defined(CMR_SECOND_PASS)
  // The cascade's double pass: pixel `at` of those the float pixel pass
  // could not certify; its label byte there is PACKED_UNCERTAIN (all ones)
  // and its depth byte 0, so xor and or put this pass's bytes in.
  if (at >= min(result[counters + OUT_SECOND], cap)) return;
  const uint k = result[hdr[HDR_OUT_SECOND] + at], pi = k % w, pj = k / w;
  const uint r = classify_pixel(int(pi), int(pj));
  if ((r & RESULT_UNCERTAIN) != 0u) {
    to_host(k, counters, list, cap);
    return;
  }
  const uint word = (pj - hdr[HDR_FIRST_TILE_ROW] * TILE) * stride + pi / 4u, shift = 8u * (pi % 4u);
  atomicXor(result[word], (PACKED_UNCERTAIN ^ (r & RESULT_LABEL_MASK)) << shift);
  if (hdr[HDR_DEPTH_PLANE] != 0u)
    atomicOr(result[hdr[HDR_TILE_ROWS] * TILE * stride + word], ((r >> RESULT_DEPTH_SHIFT) & 255u) << shift);
  return;
#elif defined(CMR_PIXEL_PASS)
  // The pixel pass: a workgroup per queued tile (and on, past the 65535
  // groups of a dispatch), an invocation per pixel (x, y) of it, so that a
  // short queue still spreads over the device. A queued tile's words start
  // at 0 (the host clears the planes), and each pixel ors its bytes in.
  const uint x = gl_LocalInvocationID.x % TILE, y = gl_LocalInvocationID.x / TILE;
  const uint queued = result[counters + OUT_QUEUED], h = hdr[HDR_HEIGHT];
  const uint plane = hdr[HDR_TILE_ROWS] * TILE * stride;
  for (uint q = gl_WorkGroupID.x; q < queued; q += gl_NumWorkGroups.x) {
    const uint t = result[queue + q];
    const uint tx = t % tiles_x, row = (t / tiles_x) * TILE + y;  // the pixel's row in the run
    const uint pi = tx * TILE + x, pj = hdr[HDR_FIRST_TILE_ROW] * TILE + row;
    if (pi >= w || pj >= h) continue;
    const uint r = classify_pixel(int(pi), int(pj));
    uint label = r & RESULT_LABEL_MASK;
    if ((r & RESULT_UNCERTAIN) != 0u) {
      label = PACKED_UNCERTAIN;
      uint s = cap;
      if (hdr[HDR_CASCADE] != 0u) {  // to the double pass while its list has room
        s = atomicAdd(result[counters + OUT_SECOND], 1u);
        if (s < cap) {
          result[hdr[HDR_OUT_SECOND] + s] = pj * w + pi;
          if (s % 64u == 0u) atomicAdd(result[counters + OUT_SECOND_GROUPS_X], 1u);
        }
      }
      if (s >= cap) to_host(pj * w + pi, counters, list, cap);
    }
    const uint at_word = row * stride + pi / 4u, shift = 8u * (pi % 4u);
    atomicOr(result[at_word], label << shift);
    if (hdr[HDR_DEPTH_PLANE] != 0u) atomicOr(result[plane + at_word], ((r >> RESULT_DEPTH_SHIFT) & 255u) << shift);
  }
#else
  // Listed pixel number `at` (the host lists the pixels it could not
  // decide by whole blocks, block by block, so that neighbouring
  // invocations, which a GPU or llvmpipe runs in lock step, get
  // neighbouring, similar pixels).
  if (at >= hdr[HDR_LISTED]) return;
  REAL2 ij = DATA(hdr[HDR_LIST_OFFSET] + at);
  result[at] = classify_pixel(int(ij.x), int(ij.y));
  return;
#endif
}
#endif  // CMR_REGION_PRESENT
