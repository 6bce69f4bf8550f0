// The program's method at the current inputs, shared by glsl/shade.frag and glsl/evaluate.comp.
// "method.glsl" is resolved by src/gpu/shaders.rs to the program's file in glsl/methods/. It
// defines either `real3 methodNormal()` (the shading normal; lit by shade(), or by `methodShade(N)`
// when it defines METHOD_SHADE), or, when it defines METHOD_COLOR, `real3 methodColor()`, in the
// precision vocabulary of glsl/common.glsl; the results leave here as float32.
#include "method.glsl"

// The method's colour, and its shading normal with w = 1 (w = 0: the method has none).
void evaluateMethod(out vec3 color, out vec4 normal) {
#ifdef METHOD_COLOR
    color = F3(methodColor());
    normal = vec4(0.0);
#else
    real3 N = methodNormal();
    normal = vec4(F3(N), 1.0);
#ifdef METHOD_SHADE
    color = F3(methodShade(N));
#else
    color = F3(shade(N));
#endif
#endif
}
