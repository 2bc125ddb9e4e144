#version 450
#extension GL_GOOGLE_include_directive : require
// The published method per pixel in a fragment shader (published_fp64.glsl).
#include "published_fp64.glsl"
layout(location = 0) out uint result;
void main() { result = published_label(int(gl_FragCoord.x), int(gl_FragCoord.y)); }
