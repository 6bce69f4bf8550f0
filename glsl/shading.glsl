#ifndef SHADING_GLSL
#define SHADING_GLSL
// The lighting model of the papers (docs/formulas.md#lighting-model), identical for every method:
//   I = k_a I_a + sum_lights I_L (k_d max(0, N.L) + k_s max(0, N.H)^n)
// Directional lights, viewer at infinity: L and H are per-frame constants in view space.
// max(0, x)^n is taken as 0 at x == 0 so that n == 0 gives no NaN (pow(0, 0) is undefined in GLSL).
// In the precision vocabulary of glsl/common.glsl: computed in `real`.
real3 shade(real3 N) {
    real3 c = R3(params.ambient.rgb);
    for (int i = 0; i < LIGHT_COUNT; ++i) {
        real d = max(dot(N, R3(params.lightDir[i].xyz)), R(0.0));
        real s = max(dot(N, R3(params.halfVec[i].xyz)), R(0.0));
        real sp = HAS_SPECULAR && s > R(0.0) ? pow(s, R(params.specular.w)) : R(0.0);
        c += R3(params.lightColor[i].rgb) * (R3(params.diffuse.rgb) * d + R3(params.specular.rgb) * sp);
    }
    return c;
}
#endif
