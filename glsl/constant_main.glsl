// The cost floor: the same draw with a constant colour and no shading at all (glsl/constant.frag;
// COLOR_ONLY, glsl/constant_color.frag: without the normal output).
layout(location = 0) out vec4 outColor;
#ifndef COLOR_ONLY
layout(location = 1) out vec4 outNormal;
#endif

void main() {
    outColor = params.constColor;
#ifndef COLOR_ONLY
    outNormal = vec4(0.0);
#endif
}
