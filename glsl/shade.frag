#version 450
#define STAGE_FRAGMENT
#include "common.glsl"
#include "shading.glsl"

layout(location = 0) out vec4 outColor;    // linear colour, alpha 1 = covered
layout(location = 1) out vec4 outNormal;   // the shading normal the method used, w 1 = has one

// "method.glsl" is resolved by src/shaders.rs to the program's file in glsl/methods/. It defines
// either `vec3 methodNormal()` (the shading normal; lit by shade(), or by `methodShade(N)` when
// it defines METHOD_SHADE), or, when it defines METHOD_COLOR, `vec3 methodColor()`.
#include "method.glsl"

void main() {
#ifdef METHOD_COLOR
    outColor = vec4(methodColor(), 1.0);
    outNormal = vec4(0.0);
#else
    vec3 N = methodNormal();
    outNormal = vec4(N, 1.0);
#ifdef METHOD_SHADE
    outColor = vec4(methodShade(N), 1.0);
#else
    outColor = vec4(shade(N), 1.0);
#endif
#endif
}
