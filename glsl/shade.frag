#version 450
#define STAGE_FRAGMENT
#include "common.glsl"
#include "shading.glsl"

layout(location = 0) out vec4 outColor;    // linear colour, alpha 1 = covered
layout(location = 1) out vec4 outNormal;   // the shading normal the method used, w 1 = has one

#include "method_main.glsl"

void main() {
    vec3 color;
    evaluateMethod(color, outNormal);
    outColor = vec4(color, 1.0);
}
