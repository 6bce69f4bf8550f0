#version 450
#define STAGE_VERTEX
#include "common.glsl"

layout(location = 0) in vec3 inPosition;   // model space (fitted to the unit sphere)
#ifdef IN_NORMAL
layout(location = 1) in vec3 inNormal;     // view space, unit (transformed in f64 on the CPU)
#endif

// The id pass and every method pass must rasterize identically: they share this code, and
// lavapipe compiles it deterministically. (`invariant gl_Position` would say so formally, but
// Mesa's SPIR-V front end warns that the decoration is not allowed on the gl_PerVertex member
// and ignores it.) tests/gpu.rs checks that both passes cover exactly the same pixels.

void main() {
    gl_Position = params.mvp * vec4(inPosition, 1.0);
#ifdef IN_NORMAL
    vNormal = inNormal;
#endif
#ifdef IN_BARY
    int corner = gl_VertexIndex % 3;
    vBary = vec3(corner == 0, corner == 1, corner == 2);
#endif
#ifdef IN_PRIM
    vPrim = uint(gl_VertexIndex / 3);
#endif
}
