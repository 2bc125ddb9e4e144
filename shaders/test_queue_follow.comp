#version 450
// vk::ComputePipeline's chain test, the follow-up pass: queued item q <
// result[0] gets result[8 + v[0] + q] = 10 v[1 + at] + 1, at = result[8 + q]
// (what the first pass queued, read after its writes).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Input { uint v[]; };
layout(std430, set = 0, binding = 1) buffer Result { uint result[]; };
void main() {
  const uint q = gl_GlobalInvocationID.x;
  if (q >= result[0]) return;
  result[8u + v[0] + q] = 10u * v[1u + result[8u + q]] + 1u;
}
