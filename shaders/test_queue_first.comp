#version 450
// vk::ComputePipeline's chain test (tests/vk/compute_pipeline_test.cpp),
// first pass: item at < v[0] whose value v[1 + at] is odd is queued,
// result[8 + q] = at; result[0] counts the queued items and result[1] the
// follow-up's groups of 64 (result[2], result[3] stay 1).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Input { uint v[]; };
layout(std430, set = 0, binding = 1) buffer Result { uint result[]; };
void main() {
  const uint at = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (at >= v[0] || (v[1u + at] & 1u) == 0u) return;
  const uint q = atomicAdd(result[0], 1u);
  result[8u + q] = at;
  if (q % 64u == 0u) atomicAdd(result[1], 1u);
}
