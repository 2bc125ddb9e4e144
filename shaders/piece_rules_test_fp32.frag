#version 450
#extension GL_GOOGLE_include_directive : require
// Runs the shader's piece decision (piece_rules.glsl) on a table of
// coefficient vectors, one case per pixel (row by row), in fp32: the storage
// buffer holds CASE_STRIDE pairs per case, (n1, eta) then n1 pairs (value,
// bound). result = the Piece code (cmr::Piece order). tests/vk/piece_rules_test.cpp.
#define REAL float
#define REAL2 vec2
layout(constant_id = 0) const int CASE_STRIDE = 16;
layout(constant_id = 1) const int COLUMNS = 256;  // case = row * COLUMNS + column
layout(std430, set = 0, binding = 0) readonly buffer Cases { REAL2 data[]; };
layout(location = 0) out uint result;

#include "piece_rules.glsl"

REAL2 coeff_at(uint e, bool eta, int p, int k) { return data[e * uint(CASE_STRIDE) + 1u + uint(k)]; }

void main() {
  uint c = uint(gl_FragCoord.y) * uint(COLUMNS) + uint(gl_FragCoord.x);
  REAL2 head = data[c * uint(CASE_STRIDE)];
  result = uint(decide_piece(c, head.y != REAL(0), 0, int(head.x)));
}
