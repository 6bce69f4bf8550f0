// The outputs and main() of glsl/shade.frag and glsl/shade_color.frag (COLOR_ONLY: no normal
// output, the method's normal computed and left unused).
layout(location = 0) out vec4 outColor;    // linear colour, alpha 1 = covered
#ifndef COLOR_ONLY
layout(location = 1) out vec4 outNormal;   // the shading normal the method used, w 1 = has one
#endif

#include "method_main.glsl"

void main() {
    vec3 color;
#ifdef COLOR_ONLY
    vec4 normal;
    evaluateMethod(color, normal);
#else
    evaluateMethod(color, outNormal);
#endif
    outColor = vec4(color, 1.0);
}
