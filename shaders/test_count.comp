#version 450
// vk::ComputePipeline's test shader (tests/vk/compute_pipeline_test.cpp):
// item `at` of `count` gets input[at mod length] * 3 + at + add, so that a
// wrong index, a missed item or a write past the end shows.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Input { uint v[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Result { uint result[]; };
layout(push_constant) uniform Push {
  uint count;
  uint add;
} pc;
void main() {
  const uint at = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (at >= pc.count) return;
  result[at] = v[at % uint(v.length())] * 3u + at + pc.add;
}
