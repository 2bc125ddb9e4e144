#version 450
#extension GL_GOOGLE_include_directive : require
// Regions of a point of a polynomial space curve moving in a plane, one pixel
// per invocation: the GPU mirror of one part of
// cmr::SpaceRegionProblem::classify (region/space_region.cpp). One run
// judges one moved segment (Algorithm 1 on lambda3, bezierize/space_lambda.hpp
// and decide.hpp) or one varying joint's curvature jump, in double precision
// with a running error bound on every quantity (as cmr::Bounded). A result
// that rests on a sign this arithmetic cannot certify is flagged, and the
// host (vk/space_region_vk.cpp) then classifies the pixel on the CPU, so the
// labels equal the CPU backend's.
//
// Buffer (std430; names in shaders/space_region_layout.h, shared with the
// packer vk/space_region_vk.cpp): uint hdr[SPACE_HDR_WORDS], then dvec2
// data[] (value, error bound), offsets counting pairs. SPACE_HDR_MODE:
// SPACE_MODE_SEGMENT or SPACE_MODE_JOINT; SPACE_HDR_COLUMN_OFFSET: the plane
// coordinate a per column (width entries); SPACE_HDR_ROW_OFFSET: b per row
// (height entries); SPACE_HDR_PLANE_OFFSET: the plane (O, U, V: nine
// entries, exact); SPACE_HDR_DATA_OFFSET: the segment data: for each of the
// DEG+1 Bezier points B_k = F_k + m_k Q (Q the moved point), the entries
// F_k.x, F_k.y, F_k.z, m_k; a joint run has the left segment's then the
// right segment's.
// Rational curves (RAT = 1, SPACE_MODE_RATIONAL_SEGMENT and _JOINT): the
// column and row entries hold the offsets x = a - a0 per column and
// y = b - b0 per row (with rounding bounds), SPACE_HDR_DATA_OFFSET the
// polynomials in (x, y) the host derived exactly
// (SpaceRegionProblem::rational_lambda3 / rational_jump): terms x^p y^q,
// p + q <= D, ordered p = 0..D, q = 0..D-p. A segment: the NL coefficients
// of lambda3 (degree 11n-18), each of degree hdr[SPACE_HDR_DEGREE]; then
// Algorithm 1 as for a polynomial segment. A joint: gl, gr, D, of degrees
// hdr[SPACE_HDR_DEGREE + 0, 1, 2]; the jump rule of a polynomial joint.
// Result word: segments: curvature code (0 increasing, 1 decreasing,
// 2 non-monotone, 3 undecided, 4 constant) | depth << 8; joints: jump sign
// + 1; or RESULT_UNCERTAIN.
#define REAL double
#define REAL2 dvec2
#define K_ROUND 2.220446049250313080847263336181640625e-16LF     // 2^-52
#define K_TINY 9.332636185032188789900895447238171696171e-302LF  // 2^-1000
#include "space_region_layout.h"

layout(constant_id = 0) const int DEG = 3;    // degree n of the segments, 2..7
layout(constant_id = 1) const int MAXD = 12;  // maximum subdivision depth D
layout(constant_id = 2) const int RAT = 0;    // 1: a rational curve (modes 2 and 3)

const int M = DEG - 1;          // hodograph degree
const int NC = 2 * DEG - 3;     // coefficients of each component of c = P' x P'' (degree 2n-4)
const int NC2 = 4 * DEG - 7;    // |c|^2 (4n-8)
const int NG = 2 * DEG - 1;     // g = |P'|^2 (2n-2)
const int NLP = 6 * DEG - 10;   // lambda3 of a polynomial curve (6n-11)
const int NL = RAT * (11 * DEG - 17) + (1 - RAT) * NLP;  // the lambda3 Algorithm 1 runs on
const int MAXPOLY = 8;          // highest degree of a rational run's polynomial in (x, y)

layout(std430, set = 0, binding = 0) readonly buffer SpaceData {
  uint hdr[SPACE_HDR_WORDS];
  REAL2 data[];
};
// One invocation per pixel of a run (vk/compute_pipeline.hpp's interface):
// pixel SPACE_HDR_FIRST_PIXEL + at of the image, row-major.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 1) writeonly buffer SpaceResult {
  uint result_words[];
};

#include "bounded.glsl"
#include "piece_rules.glsl"
// a / d for an exact integer d != 0.
REAL2 b_div_int(REAL2 a, REAL d) {
  precise REAL r = a.x / d;
  precise REAL e = (a.y / abs(d)) * (REAL(1) + REAL(2) * K_ROUND) + K_ROUND * abs(r) + K_TINY;
  return REAL2(r, e);
}
REAL2 b_exact(REAL v) { return REAL2(v, REAL(0)); }

// C(n, k), exact in double for the sizes here (n <= 6 DEG).
REAL binom(int n, int k) {
  REAL c = REAL(1);
  for (int i = 0; i < k; ++i) c = c * REAL(n - i) / REAL(i + 1);
  return c;
}

REAL2 Q[3];
REAL2 B[DEG + 1][3];

// Bezier points of the segment whose data start at entry `at`.
void load_bezier(uint at) {
  for (int k = 0; k <= DEG; ++k) {
    REAL2 m = data[at + uint(4 * k + 3)];
    for (int c = 0; c < 3; ++c) B[k][c] = b_add(data[at + uint(4 * k + c)], b_mul(m, Q[c]));
  }
}

REAL2 lam[NL];

// lambda3 = (|c|^2)' g - 3 |c|^2 g' from B (space_lambda.hpp's formulas).
void lambda3() {
  REAL2 q[DEG][3];
  for (int i = 0; i < DEG; ++i)
    for (int c = 0; c < 3; ++c) q[i][c] = b_mul(b_exact(REAL(DEG)), b_sub(B[i + 1][c], B[i][c]));
  // c_k = sum_{i<j, i+j-1=k} (j-i) C(m,i) C(m,j) / C(2m-2,k) (q_i x q_j)
  REAL2 cc[3][NC];
  for (int k = 0; k < NC; ++k)
    for (int c = 0; c < 3; ++c) cc[c][k] = REAL2(0);
  for (int i = 0; i <= M; ++i)
    for (int j = i + 1; j <= M; ++j) {
      int k = i + j - 1;
      REAL2 w = b_exact(REAL(j - i) * binom(M, i) * binom(M, j));
      REAL2 x0 = b_sub(b_mul(q[i][1], q[j][2]), b_mul(q[i][2], q[j][1]));
      REAL2 x1 = b_sub(b_mul(q[i][2], q[j][0]), b_mul(q[i][0], q[j][2]));
      REAL2 x2 = b_sub(b_mul(q[i][0], q[j][1]), b_mul(q[i][1], q[j][0]));
      cc[0][k] = b_add(cc[0][k], b_mul(w, x0));
      cc[1][k] = b_add(cc[1][k], b_mul(w, x1));
      cc[2][k] = b_add(cc[2][k], b_mul(w, x2));
    }
  for (int k = 0; k < NC; ++k)
    for (int c = 0; c < 3; ++c) cc[c][k] = b_div_int(cc[c][k], binom(2 * M - 2, k));
  // |c|^2: the three products summed before the one division per coefficient.
  REAL2 c2[NC2];
  for (int k = 0; k < NC2; ++k) {
    REAL2 s = REAL2(0);
    for (int i = max(0, k - (NC - 1)); i <= min(k, NC - 1); ++i) {
      int j = k - i;
      REAL2 d = b_add(b_add(b_mul(cc[0][i], cc[0][j]), b_mul(cc[1][i], cc[1][j])), b_mul(cc[2][i], cc[2][j]));
      s = b_add(s, b_mul(b_exact(binom(NC - 1, i) * binom(NC - 1, j)), d));
    }
    c2[k] = b_div_int(s, binom(NC2 - 1, k));
  }
  // g = |P'|^2: sum_{i<=j} (1 or 2) C(m,i) C(m,j) / C(2m,i+j) q_i.q_j
  REAL2 g[NG];
  for (int k = 0; k < NG; ++k) g[k] = REAL2(0);
  for (int i = 0; i <= M; ++i)
    for (int j = i; j <= M; ++j) {
      REAL2 d = b_add(b_add(b_mul(q[i][0], q[j][0]), b_mul(q[i][1], q[j][1])), b_mul(q[i][2], q[j][2]));
      g[i + j] = b_add(g[i + j], b_mul(b_exact(REAL(i == j ? 1 : 2) * binom(M, i) * binom(M, j)), d));
    }
  for (int k = 0; k < NG; ++k) g[k] = b_div_int(g[k], binom(2 * M, k));
  // Derivatives (one spare entry: NC2 - 1 is 0 for a quadratic).
  REAL2 c2d[NC2], gd[NG];
  for (int k = 0; k + 1 < NC2; ++k) c2d[k] = b_mul(b_exact(REAL(NC2 - 1)), b_sub(c2[k + 1], c2[k]));
  for (int k = 0; k + 1 < NG; ++k) gd[k] = b_mul(b_exact(REAL(NG - 1)), b_sub(g[k + 1], g[k]));
  // lambda3_k = [c2' g]_k - 3 [c2 g']_k, each product in Bernstein form.
  int p1 = NC2 - 2, p2 = NG - 1, p3 = NC2 - 1, p4 = NG - 2;  // degrees of c2', g, c2, g'
  for (int k = 0; k < NLP; ++k) {
    REAL2 x = REAL2(0), y = REAL2(0);
    if (p1 >= 0) {
      for (int i = max(0, k - p2); i <= min(k, p1); ++i)
        x = b_add(x, b_mul(b_exact(binom(p1, i) * binom(p2, k - i)), b_mul(c2d[i], g[k - i])));
      x = b_div_int(x, binom(NLP - 1, k));
    }
    for (int i = max(0, k - p4); i <= min(k, p3); ++i)
      y = b_add(y, b_mul(b_exact(binom(p3, i) * binom(p4, k - i)), b_mul(c2[i], gd[k - i])));
    y = b_div_int(y, binom(NLP - 1, k));
    lam[k] = b_sub(x, b_mul(b_exact(REAL(3)), y));
  }
}

// Algorithm 1 on lam: decide.hpp's traverse with BernsteinSource (halves at
// t = 1/2, right halves on a stack) and MonotonicityFold (classify.cpp); each
// piece decided by the shared rule (piece_rules.glsl's decide_piece, the one
// tests/vk/piece_rules_test.cpp checks against the C++ core) on `cur`.
REAL2 cur[NL];
REAL2 pending[(MAXD + 1) * NL];
REAL2 work[NL];

REAL2 coeff_at(uint e, bool eta, int p, int k) { return cur[k]; }
int piece_rule() { return decide_piece(0u, false, 0, NL); }

uint algorithm1() {
  for (int k = 0; k < NL; ++k) cur[k] = lam[k];
  int level = 0, j = 0, sp = 0;
  bool inc = false, dec = false, undecided = false;
  int deepest = 0;
  for (;;) {
    int p = piece_rule();
    if (p == P_UNCERTAIN) return RESULT_UNCERTAIN;
    if (p == P_SPLIT && level < MAXD) {
      ++level;
      j *= 2;
      // cur -> its left half; the right half is pushed.
      for (int i = 0; i < NL; ++i) work[i] = cur[i];
      int base = sp * NL;
      pending[base + NL - 1] = work[NL - 1];
      for (int r = 1; r < NL; ++r) {
        for (int i = 0; i + r < NL; ++i) work[i] = b_half(b_add(work[i], work[i + 1]));
        cur[r] = work[0];
        pending[base + NL - 1 - r] = work[NL - 1 - r];
      }
      ++sp;
      continue;
    }
    // MonotonicityFold::visit
    if (p == P_ZERO) return 4u | (uint(level) << 8);
    if (p == P_NONMONO) return 2u | (uint(level) << 8);
    if (p == P_INC) inc = true;
    else if (p == P_DEC) dec = true;
    else undecided = true;
    deepest = max(deepest, level);
    if (inc && dec) return 2u | (uint(level) << 8);
    while (level > 0 && (j & 1) == 1) {
      --level;
      j >>= 1;
    }
    if (level == 0) break;
    ++j;
    --sp;
    for (int i = 0; i < NL; ++i) cur[i] = pending[sp * NL + i];
  }
  if (undecided) return 3u | (uint(MAXD) << 8);
  return (inc ? 0u : 1u) | (uint(deepest) << 8);
}

REAL2 dot3(REAL2 a[3], REAL2 b[3]) { return b_add(b_add(b_mul(a[0], b[0]), b_mul(a[1], b[1])), b_mul(a[2], b[2])); }

// sign(kappa_R - kappa_L) of space_region.cpp's jump_sign3: from the legs
// at the joint, sign(|ar x br|^2 |al|^6 - |al x bl|^2 |ar|^6).
// The joint rule (space_region.cpp's jump_sign3): both legs certified
// non-zero, then the certified sign of d; otherwise the host decides.
uint jump_word(REAL2 gl, REAL2 gr, REAL2 d) {
  if (b_sign(gl) != 1 || b_sign(gr) != 1) return RESULT_UNCERTAIN;  // zero tangents: the host
  int s = b_sign(d);
  if (s == SIGN_UNKNOWN || s == 0) return RESULT_UNCERTAIN;
  return uint(s + 1);
}

uint joint_sign(uint left, uint right) {
  load_bezier(left);
  REAL2 al[3], bl[3], xl[3];
  for (int c = 0; c < 3; ++c) {
    al[c] = b_sub(B[DEG - 1][c], B[DEG][c]);
    bl[c] = b_sub(B[DEG - 2][c], B[DEG - 1][c]);
  }
  load_bezier(right);
  REAL2 ar[3], br[3], xr[3];
  for (int c = 0; c < 3; ++c) {
    ar[c] = b_sub(B[1][c], B[0][c]);
    br[c] = b_sub(B[2][c], B[1][c]);
  }
  REAL2 gl = dot3(al, al), gr = dot3(ar, ar);
  xl[0] = b_sub(b_mul(al[1], bl[2]), b_mul(al[2], bl[1]));
  xl[1] = b_sub(b_mul(al[2], bl[0]), b_mul(al[0], bl[2]));
  xl[2] = b_sub(b_mul(al[0], bl[1]), b_mul(al[1], bl[0]));
  xr[0] = b_sub(b_mul(ar[1], br[2]), b_mul(ar[2], br[1]));
  xr[1] = b_sub(b_mul(ar[2], br[0]), b_mul(ar[0], br[2]));
  xr[2] = b_sub(b_mul(ar[0], br[1]), b_mul(ar[1], br[0]));
  REAL2 a2l = dot3(xl, xl), a2r = dot3(xr, xr);
  REAL2 d = b_sub(b_mul(a2r, b_mul(gl, b_mul(gl, gl))), b_mul(a2l, b_mul(gr, b_mul(gr, gr))));
  return jump_word(gl, gr, d);
}

// Polynomials in the offsets (x, y) of the moved point (modes 2 and 3).
REAL2 XP[MAXPOLY + 1], YP[MAXPOLY + 1];
void plane_powers(REAL2 x, REAL2 y) {
  XP[0] = b_exact(REAL(1));
  YP[0] = b_exact(REAL(1));
  for (int i = 1; i <= MAXPOLY; ++i) {
    XP[i] = b_mul(XP[i - 1], x);
    YP[i] = b_mul(YP[i - 1], y);
  }
}
uint poly_terms(int D) { return uint((D + 1) * (D + 2) / 2); }
// sum_p x^p (sum_q c_pq y^q) from the terms at entry `at`.
REAL2 plane_poly(uint at, int D) {
  REAL2 s = REAL2(0);
  uint t = at;
  for (int p = 0; p <= D; ++p) {
    REAL2 inner = REAL2(0);
    for (int q = 0; p + q <= D; ++q) inner = b_add(inner, b_mul(data[t++], YP[q]));
    s = b_add(s, b_mul(inner, XP[p]));
  }
  return s;
}

// The result word of pixel (col, row) for this run's mode.
uint classify_pixel(uint col, uint row) {
  uint mode = hdr[SPACE_HDR_MODE];
  if (mode == SPACE_MODE_RATIONAL_SEGMENT || mode == SPACE_MODE_RATIONAL_JOINT) {  // polynomials in (x, y)
    int D0 = int(hdr[SPACE_HDR_DEGREE]), D1 = int(hdr[SPACE_HDR_DEGREE + 1u]), D2 = int(hdr[SPACE_HDR_DEGREE + 2u]);
    if (D0 > MAXPOLY || D1 > MAXPOLY || D2 > MAXPOLY) return RESULT_UNCERTAIN;
    plane_powers(data[hdr[SPACE_HDR_COLUMN_OFFSET] + col], data[hdr[SPACE_HDR_ROW_OFFSET] + row]);
    uint at = hdr[SPACE_HDR_DATA_OFFSET];
    if (mode == SPACE_MODE_RATIONAL_SEGMENT) {
      for (int k = 0; k < NL; ++k) {
        lam[k] = plane_poly(at, D0);
        at += poly_terms(D0);
      }
      return algorithm1();
    }
    REAL2 gl = plane_poly(at, D0);
    at += poly_terms(D0);
    REAL2 gr = plane_poly(at, D1);
    at += poly_terms(D1);
    return jump_word(gl, gr, plane_poly(at, D2));
  }
  REAL a = data[hdr[SPACE_HDR_COLUMN_OFFSET] + col].x, b = data[hdr[SPACE_HDR_ROW_OFFSET] + row].x;
  uint pl = hdr[SPACE_HDR_PLANE_OFFSET];
  for (int c = 0; c < 3; ++c)
    Q[c] = b_add(b_add(b_exact(data[pl + uint(c)].x), b_mul(b_exact(a), b_exact(data[pl + uint(3 + c)].x))),
                 b_mul(b_exact(b), b_exact(data[pl + uint(6 + c)].x)));
  uint at = hdr[SPACE_HDR_DATA_OFFSET];
  if (mode == SPACE_MODE_SEGMENT) {
    load_bezier(at);
    lambda3();
    return algorithm1();
  }
  return joint_sign(at, at + uint(4 * (DEG + 1)));
}

void main() {
  const uint at = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (at >= hdr[SPACE_HDR_PIXELS]) return;
  const uint k = hdr[SPACE_HDR_FIRST_PIXEL] + at, w = hdr[SPACE_HDR_WIDTH];
  result_words[at] = classify_pixel(k % w, k / w);
}
