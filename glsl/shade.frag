#version 450
#define STAGE_FRAGMENT
#include "common.glsl"
#include "shading.glsl"

layout(location = 0) out vec4 outColor;    // linear colour, alpha 1 = covered
layout(location = 1) out vec4 outNormal;   // the shading normal the method used, w 1 = has one

// "method.glsl" is resolved by src/shaders.rs to the program's file in glsl/methods/, which
// defines: vec3 methodNormal();
#include "method.glsl"

void main() {
    vec3 N = methodNormal();
    outNormal = vec4(N, 1.0);
    outColor = vec4(shade(N), 1.0);
}
