// Certified arithmetic on pairs (value, bound on |exact - value|): the GPU
// mirror of cmr::Bounded (numeric/bounded.hpp), shared by the planar
// (region_common.glsl) and the space (space_region_fp64.comp) region shaders.
// The includer defines REAL, REAL2, K_ROUND (twice the unit roundoff) and
// K_TINY (absolute slack for underflow, also covering flush-to-zero).

REAL2 b_add(REAL2 a, REAL2 b) {
  precise REAL r = a.x + b.x;
  precise REAL e = a.y + b.y + K_ROUND * abs(r);
  return REAL2(r, e);
}
REAL2 b_sub(REAL2 a, REAL2 b) {
  precise REAL r = a.x - b.x;
  precise REAL e = a.y + b.y + K_ROUND * abs(r);
  return REAL2(r, e);
}
REAL2 b_mul(REAL2 a, REAL2 b) {
  precise REAL r = a.x * b.x;
  precise REAL e = abs(a.x) * b.y + abs(b.x) * a.y + a.y * b.y + K_ROUND * abs(r) + K_TINY;
  return REAL2(r, e);
}
REAL2 b_half(REAL2 a) { return REAL2(REAL(0.5) * a.x, REAL(0.5) * a.y + K_TINY); }
