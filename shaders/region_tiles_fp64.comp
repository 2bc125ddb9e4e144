#version 450
#extension GL_GOOGLE_include_directive : require
// The tile pass of the region shader's whole share (region_tiles.glsl) in
// double precision; the pixel pass that follows it is region_fp64.comp.
// A module of its own, so that the pixel pipelines carry no box code
// (inlined and then dropped, it had cost lavapipe's one-shot `cmr region`
// 130 ms of compile).
#define CMR_TILE_PASS
#define REAL double
#define K_DATA_BASE HDR_DATA_BASE_F64
#define REAL2 dvec2
#define K_ROUND 2.220446049250313080847263336181640625e-16LF  // 2^-52
#define K_TINY 9.332636185032188789900895447238171696171e-302LF  // 2^-1000
#include "region_common.glsl"
