#version 450
#extension GL_GOOGLE_include_directive : require
// The published method per pixel in a compute shader (published_fp64.glsl):
// invocation `at` is pixel (at mod width, at / width), row-major
// (vk/compute_pipeline.hpp's interface).
#include "published_fp64.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 1) writeonly buffer Result { uint result[]; };
void main() {
  const uint at = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (at >= uint(pc.width * pc.height)) return;
  result[at] = published_label(int(at % uint(pc.width)), int(at / uint(pc.width)));
}
