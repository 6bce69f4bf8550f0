#version 450
#define STAGE_FRAGMENT
#include "common.glsl"

// The cost floor: the same draw with a constant colour and no shading at all.
layout(location = 0) out vec4 outColor;
layout(location = 1) out vec4 outNormal;

void main() {
    outColor = params.constColor;
    outNormal = vec4(0.0);
}
