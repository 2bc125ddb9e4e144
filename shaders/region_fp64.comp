#version 450
#extension GL_GOOGLE_include_directive : require
// Region shader, the culled share: one invocation per pixel the host lists,
// in double precision (needs shaderFloat64).
#define REAL double
#define K_DATA_BASE HDR_DATA_BASE_F64
#define REAL2 dvec2
#define K_ROUND 2.220446049250313080847263336181640625e-16LF  // 2^-52
#define K_TINY 9.332636185032188789900895447238171696171e-302LF  // 2^-1000
#include "region_common.glsl"
