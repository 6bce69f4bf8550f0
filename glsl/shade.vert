#version 450
#define STAGE_VERTEX
#include "common.glsl"

layout(location = 0) in vec3 inPosition;   // model space (fitted to the unit sphere)
#ifdef ATTR_NORMAL
layout(location = 1) in vec3 inNormal;     // view space, unit (transformed in f64 on the CPU)
#endif
#ifdef ATTR_FLAT
layout(location = 2) in vec3 inFlat;       // the triangle's unit flat normal, view space
#endif
#ifdef ATTR_CORNERS
layout(location = 3) in vec3 inN0;         // the triangle's three vertex normals, on every corner
layout(location = 4) in vec3 inN1;
layout(location = 5) in vec3 inN2;
#endif
#ifdef ATTR_PN
layout(location = 6) in vec3 inPn01;       // PN mid-edge normals (set up on the CPU in f64)
layout(location = 7) in vec3 inPn12;
layout(location = 8) in vec3 inPn20;
#endif
#ifdef ATTR_WINDOW
layout(location = 9) in vec3 inW0;         // the triangle's window-space corners (x, y, 0),
layout(location = 10) in vec3 inW1;        // on every corner
layout(location = 11) in vec3 inW2;
#endif

#ifdef IN_COLOR
#include "shading.glsl"
#endif
#ifdef IN_QUAT
#include "quaternion.glsl"
#endif

// The id pass and every method pass must rasterize identically: they share this code, and
// lavapipe compiles it deterministically. (`invariant gl_Position` would say so formally, but
// Mesa's SPIR-V front end warns that the decoration is not allowed on the gl_PerVertex member
// and ignores it.) tests/gpu.rs checks that both passes cover the same pixels
// (the coverage masks, pixel by pixel).

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
#ifdef IN_FLAT
    vFlat = inFlat;
#endif
#ifdef IN_CORNERS
    vN0 = inN0;
    vN1 = inN1;
    vN2 = inN2;
#endif
#ifdef IN_WINDOW
    vW0 = inW0.xy;
    vW1 = inW1.xy;
    vW2 = inW2.xy;
#endif
#ifdef IN_PN
    vPn01 = inPn01;
    vPn12 = inPn12;
    vPn20 = inPn20;
#endif
#ifdef IN_COLOR
    // Gouraud: light the vertex (docs/formulas.md#gouraud-shading)
    vColor = F3(shade(R3(inNormal)));
#endif
#ifdef IN_QUAT
#ifdef QUAT_LOCAL
    real3 t, b;                                // per-triangle frame whose +Z is the flat normal
    onb(R3(inFlat), t, b);
    vQuat = F3(quatFromNormal(real3(dot(R3(inNormal), t), dot(R3(inNormal), b), dot(R3(inNormal), R3(inFlat)))));
#else
    vQuat = F3(quatFromNormal(R3(inNormal)));  // view space
#endif
#endif
}
