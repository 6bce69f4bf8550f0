#ifndef SHADING_GLSL
#define SHADING_GLSL
// The lighting model of the seeds (FORMULAS.md 1.2), identical for every method:
//   I = k_a I_a + sum_lights I_L (k_d max(0, N.L) + k_s max(0, N.H)^n)
// Directional lights, viewer at infinity: L and H are per-frame constants in view space.
// max(0, x)^n is taken as 0 at x == 0 so that n == 0 gives no NaN (pow(0, 0) is undefined in GLSL).
vec3 shade(vec3 N) {
    vec3 c = params.ambient.rgb;
    for (int i = 0; i < LIGHT_COUNT; ++i) {
        float d = max(dot(N, params.lightDir[i].xyz), 0.0);
        float s = max(dot(N, params.halfVec[i].xyz), 0.0);
        float sp = HAS_SPECULAR && s > 0.0 ? pow(s, params.specular.w) : 0.0;
        c += params.lightColor[i].rgb * (params.diffuse.rgb * d + params.specular.rgb * sp);
    }
    return c;
}
#endif
