#version 450
#define STAGE_FRAGMENT
#include "common.glsl"

// The id pass: per covered pixel, the triangle and the interpolation weights the rasterizer used,
// for the CPU f64 evaluation of every method (src/truth.rs).
layout(location = 0) out vec4 outBary;   // xyz: weights of corners 0, 1, 2
layout(location = 1) out uint outPrim;   // triangle index + 1 (0 = background)

void main() {
    outBary = vec4(vBary, 1.0);
    outPrim = vPrim + 1u;
}
