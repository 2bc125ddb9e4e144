#version 450
#extension GL_GOOGLE_include_directive : require
// The whole share's pixel pass in single precision (a cascade's too).
#define CMR_PIXEL_PASS
#define REAL float
#define K_DATA_BASE HDR_DATA_BASE_F32
#define REAL2 vec2
#define K_ROUND 1.1920928955078125e-7  // 2^-23
#define K_TINY 7.8886090522101180541e-31  // 2^-100: covers flush-to-zero of denormals
#include "region_common.glsl"
