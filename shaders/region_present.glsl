// The region drawn straight into a window's colour image (cmr edit on a GPU):
// one fragment per pixel of the canvas (the window's top-left W x H pixels,
// pixel (i, j) = gl_FragCoord), classified by region_common.glsl exactly as
// the region shader classifies a listed pixel, and written as the legend's
// absorption (draw/draw.cpp: plain_absorb, split_absorb) for a
// reverse-subtract blend from white, so overlapping layers darken as in
// `cmr region --png`. Certified like the region shader: a pixel the device
// cannot certify is not guessed; its index is appended to the uncertain list
// (binding 2), the host decides it (certified, then exactly) and hands the
// label back through the override words (binding 1), which win over the
// shader from then on. Depth shading is not drawn here (the editor uses the
// CPU path for it).
//
// Included by region_present_fp64.frag / region_present_fp32.frag.
#define CMR_REGION_PRESENT
#include "region_common.glsl"

layout(std430, set = 0, binding = 1) readonly buffer Overrides {
  uint override_word[];  // W * H: 0 = none, else label code + 1
};
layout(std430, set = 0, binding = 2) buffer Uncertain {
  uint uncertain_count;     // atomically incremented; may exceed the capacity
  uint uncertain_capacity;  // entries uncertain_at can hold
  uint uncertain_at[];      // j * W + i of pixels the host must decide
};

layout(location = 0) out vec4 absorb;

// draw/draw.cpp's legend (kRed, kBlue, kDarkRed, kDarkBlue, kGreen).
vec3 absorb_of(uint label, uint kind) {
  if (kind == LABELS_EACH_PIECE) return label == 1u ? vec3(0.6, 0.25, 0.6) : vec3(0.0);  // kGreen
  if (kind != LABELS_SPLIT) {
    if (label == 1u) return vec3(0.0, 0.6, 0.6);
    if (label == 2u) return vec3(0.6, 0.6, 0.0);
    return vec3(0.0);
  }
  if (label == 1u) return vec3(0.0, 0.6, 0.6);     // inc-inc
  if (label == 2u) return vec3(0.85, 0.85, 0.35);  // inc-dec: maximum at the joint
  if (label == 3u) return vec3(0.35, 0.85, 0.85);  // dec-inc: minimum at the joint
  if (label == 4u) return vec3(0.6, 0.6, 0.0);     // dec-dec
  return vec3(0.0);
}

void main() {
  const bool cmr = CMR_MODE;
  uint W = hdr[HDR_WIDTH], H = hdr[HDR_HEIGHT];
  uint pi = uint(gl_FragCoord.x), pj = uint(gl_FragCoord.y);
  if (pi >= W || pj >= H) discard;
  uint index = pj * W + pi;
  uint label;
  uint given = override_word[index];
  if (given != 0u) {
    label = given - 1u;
  } else {
    if (hdr[HDR_FIXED_LEVEL0_NONE] != 0u) discard;  // every pixel is not monotone
    REAL dx = DATA(hdr[HDR_DX_OFFSET] + pi).x, dy = DATA(hdr[HDR_DY_OFFSET] + pj).x;
    set_monomials(dx, dy);
    uint r = level0(cmr);
    if (r == 0u) discard;
    if (r == UNDECIDED_YET) r = full(cmr, pixel_displacement(dx), pixel_displacement(dy));
    if ((r & UNCERTAIN) != 0u) {
      uint slot = atomicAdd(uncertain_count, 1u);
      if (slot < uncertain_capacity) uncertain_at[slot] = index;
      discard;
    }
    label = r & RESULT_LABEL_MASK;
  }
  vec3 a = absorb_of(label, hdr[HDR_LABELS]);
  if (a == vec3(0.0)) discard;
  absorb = vec4(a, 0.0);
}
