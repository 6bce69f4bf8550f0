// specular_lut (FORMULAS.md 2.20, S004 l.197-204): exact normal; the specular cos^n from a 2-D
// table indexed by (N.H, n): row floor(n + 0.5) (halves round up; GLSL round() leaves halves to
// the implementation, and the f64 twin in src/method/formulas.rs uses this same rule), clamped
// to 1..255, then linear interpolation between the 4096 cosine samples on [0, 1].
#define METHOD_SHADE
vec3 methodNormal() {
    return normalize(vNormal);
}
float lutLookup(float s) {
    if (s <= 0.0) {
        return 0.0;
    }
    int row = clamp(int(floor(params.specular.w + 0.5)), 1, LUT_ROWS) - 1;
    float f = min(s, 1.0) * float(LUT_SAMPLES - 1);
    int i0 = min(int(floor(f)), LUT_SAMPLES - 2);
    float t = f - float(i0);
    int base = row * LUT_SAMPLES + i0;
    return mix(lut[base], lut[base + 1], t);
}
vec3 methodShade(vec3 N) {
    vec3 c = params.ambient.rgb;
    for (int i = 0; i < LIGHT_COUNT; ++i) {
        float d = max(dot(N, params.lightDir[i].xyz), 0.0);
        float s = max(dot(N, params.halfVec[i].xyz), 0.0);
        c += params.lightColor[i].rgb * (params.diffuse.rgb * d + (HAS_SPECULAR ? params.specular.rgb * lutLookup(s) : vec3(0.0)));
    }
    return c;
}
