// specular_lut (docs/formulas.md#specular-table): exact normal; the specular cos^n from a 2-D
// table indexed by (N.H, n): row floor(n + 0.5) (halves round up; GLSL round() leaves halves to
// the implementation, and the f64 twin in src/method/formulas.rs uses this same rule), clamped
// to 1..255, then linear interpolation between the 4096 cosine samples on [0, 1].
#define METHOD_SHADE
real3 methodNormal() {
    return normalize(R3(vNormal));
}
real lutLookup(real s) {
    if (s <= R(0.0)) {
        return R(0.0);
    }
    int row = clamp(int(floor(R(params.specular.w) + R(0.5))), 1, LUT_ROWS) - 1;
    real f = min(s, R(1.0)) * real(LUT_SAMPLES - 1);
    int i0 = min(int(floor(f)), LUT_SAMPLES - 2);
    real t = f - real(i0);
    int base = row * LUT_SAMPLES + i0;
    return mix(R(lut[base]), R(lut[base + 1]), t);
}
real3 methodShade(real3 N) {
    real3 c = R3(params.ambient.rgb);
    for (int i = 0; i < LIGHT_COUNT; ++i) {
        real d = max(dot(N, R3(params.lightDir[i].xyz)), R(0.0));
        real s = max(dot(N, R3(params.halfVec[i].xyz)), R(0.0));
        c += R3(params.lightColor[i].rgb) * (R3(params.diffuse.rgb) * d + (HAS_SPECULAR ? R3(params.specular.rgb) * lutLookup(s) : real3(0.0)));
    }
    return c;
}
