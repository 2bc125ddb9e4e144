// Tile proofs on the device: the GPU mirror of the CPU backend's block
// proofs (region/block.cpp, classify_box_labels; region/box_eval.hpp), over
// the box of one tile's pixel displacements. Included by region_common.glsl
// in the tile pass's modules (region_tiles_fp*.comp, CMR_TILE_PASS), where
// xi_at / nu_at evaluate over the box.
//
// A coefficient polynomial P = sum c_m mu_m (poly3.hpp order) over the box
// c + [-r, r] is expanded at the centre, P(c + h) = sum_st D_st h_x^s h_y^t,
// D_st = sum_m c_m T[st][m], T[st][m] = C(a_m, s) C(b_m, t) c_x^(a_m - s)
// c_y^(b_m - t), so
//     |P - D_00| <= sum_{st != 00} |D_st| r_x^s r_y^t
// plus the rounding of the D_st, K_POLY (1 + 32 U) sum_m |c_m| G_m with
// G_m = sum over m's pairs of |T[st][m]| w_st (w_00 = 1, w_st = r_x^s r_y^t
// rounded up times 1 + 8 U); box_eval.hpp derives these counts in units of
// U = K_ROUND, which hold for float as for double. Two slacks the host's
// doubles do not need: w_st gets K_TINY (a power of a tiny radius that
// underflows or is flushed to zero must not drop its term), and G_m gets
// K_TINY / K_ROUND (a flushed T[st][m] times a coefficient up to the float
// range stays below K_POLY |c_m| K_TINY / K_ROUND).
//
// The rules (bezierize/decide.hpp, block_piece): a piece whose coefficients
// are certainly all >= 0 (<= 0; for eta strictly) over the box is a leaf in
// that direction, one whose ends certainly differ in sign (for eta: touch)
// makes every pixel of the tile fail, any other piece is split, and a split
// at level D (or past the piece budget) leaves the tile to its pixels. Every
// pixel's Algorithm 1 (2) then gives the tile's direction, or fails
// (block.cpp's comment), so a proven tile's label is its pixels' label.
// Labels only: pixels of one tile may decide at different depths, so with a
// depth map no tile is proven.

// Monomial m = x^a_m y^b_m (poly3.hpp order). T[st][m] is non-zero only for
// s <= a_m and t <= b_m (box_eval.hpp's kPairTable lists those 35 pairs).
const int EXP_X[10] = int[](0, 1, 0, 2, 1, 0, 3, 2, 1, 0);
const int EXP_Y[10] = int[](0, 0, 1, 0, 1, 2, 0, 1, 2, 3);
bool box_pair(int st, int m) { return EXP_X[st] <= EXP_X[m] && EXP_Y[st] <= EXP_Y[m]; }
int binom3(int a, int s) { return (a == 3 && (s == 1 || s == 2)) ? 3 : ((a == 2 && s == 1) ? 2 : 1); }

REAL box_t[10 * 10];  // T[st][m] at 10 st + m (0 where not a pair)
REAL box_rw[10];      // w_st (w_00 = 1)
REAL box_g[10];       // G_m

void set_box(REAL cx, REAL rx, REAL cy, REAL ry) {
  const REAL px[4] = REAL[](REAL(1), cx, cx * cx, cx * cx * cx);
  const REAL py[4] = REAL[](REAL(1), cy, cy * cy, cy * cy * cy);
  const REAL up = REAL(1) + REAL(8) * K_ROUND;
  const REAL xu = rx * up, yu = ry * up;
  for (int st = 0; st < 10; ++st) {
    REAL r = REAL(1);
    for (int k = 0; k < EXP_X[st]; ++k) r *= xu;
    for (int k = 0; k < EXP_Y[st]; ++k) r *= yu;
    box_rw[st] = st == 0 ? REAL(1) : r * up + K_TINY;
  }
  for (int m = 0; m < 10; ++m) {
    box_g[m] = K_TINY / K_ROUND;
    for (int st = 0; st < 10; ++st) {
      REAL t = REAL(0);
      if (box_pair(st, m))
        t = REAL(binom3(EXP_X[m], EXP_X[st]) * binom3(EXP_Y[m], EXP_Y[st])) * px[EXP_X[m] - EXP_X[st]] *
            py[EXP_Y[m] - EXP_Y[st]];
      box_t[10 * st + m] = t;
      box_g[m] += abs(t) * box_rw[st];
    }
  }
}

// P over the box from its coefficients c[0..n-1] (n = 10, or 3 for eta's
// degree-1 polynomials: pairs of m < 3 only), with the bound above.
REAL2 box_poly(REAL c[10], int n) {
  bool zero = true;
  for (int m = 0; m < n; ++m) zero = zero && c[m] == REAL(0);
  if (zero) return REAL2(0);  // structurally zero: exact (as at a pixel)
  REAL d[10];
  for (int st = 0; st < 10; ++st) d[st] = REAL(0);
  for (int st = 0; st < n; ++st)
    for (int m = 0; m < n; ++m) d[st] += c[m] * box_t[10 * st + m];
  REAL mag = REAL(0);
  for (int m = 0; m < n; ++m) mag += abs(c[m]) * box_g[m];
  REAL err = K_POLY * (REAL(1) + REAL(32) * K_ROUND) * mag + REAL(16) * K_TINY;
  for (int st = 1; st < n; ++st) err += abs(d[st]) * box_rw[st];
  if (WEAKEN > 0) err = ldexp(err, -WEAKEN);
  return REAL2(d[0], err);
}

REAL2 xi_box(uint at) {
  REAL c[10];
  for (int h = 0; h < 5; ++h) {
    REAL2 v = DATA(at + uint(h));
    c[2 * h] = v.x;
    c[2 * h + 1] = v.y;
  }
  return box_poly(c, 10);
}

REAL2 nu_box(uint at) {
  REAL c[10];
  REAL2 c01 = DATA(at), c2 = DATA(at + 1u);
  c[0] = c01.x; c[1] = c01.y; c[2] = c2.x;
  return box_poly(c, 3);
}

// Pieces one tile's traversal may visit before the tile is left to its
// pixels (block.cpp's budget for a block of TILE x TILE pixels).
const int BOX_BUDGET = 32;

// One segment's traversal over the box (block.cpp, box_traversal and
// BoxFold): 0 increasing (eta: positive), 1 decreasing (negative), 2 every
// pixel fails, 3 unresolved.
int box_traverse(uint e, bool eta, int maxd) {
  int levels = int(hdr[HDR_PIECE_LEVELS]);
  int level = 0, j = 0, visited = 0;
  bool inc = false, dec = false;
  for (;;) {
    int piece = (1 << level) - 1 + j;
    if (level > levels) {
      load_deep(e, eta, level, j, levels);
      piece = -1;
    }
    if (++visited > BOX_BUDGET) return 3;
    int p = decide_box_piece(e, eta, piece, eta ? NNU : NXI);
    if (p == P_UNCERTAIN) return 3;
    if (p == P_SPLIT) {
      if (level >= maxd) return 3;
      ++level;
      j *= 2;
      continue;
    }
    if (p == P_NONMONO || p == P_INFL) return 2;
    if (p == P_INC) inc = true; else dec = true;
    if (inc && dec) return 2;
    while (level > 0 && (j & 1) == 1) { --level; j >>= 1; }
    if (level == 0) break;
    ++j;
  }
  return inc ? 0 : 1;
}
