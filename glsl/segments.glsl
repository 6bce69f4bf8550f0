// Digital segments of 2^SEGMENT_K pixels (FORMULAS.md 2.16, S002 l.171-703): exact Phong at the
// segment ends (normalised span normals, the last segment's far end extrapolated past the span
// as the seed says); inside, the colour interpolated linearly (no INV_ROOT), or, with INV_ROOT,
// the normal by dichotomy between the unit end normals (S002 l.600-660). Twin:
// src/method/twins.rs segments().
#include "scanline.glsl"

vec3 segmentEnd(Span sp, float x) {
    vec3 N = spanNormal(sp, x);
    return normalize(dot(N, N) > 1e-12 ? N : sp.NA);   // an extrapolated end can pass through 0
}

// The unit normals at the ends of the fragment's segment and its place t = v / 2^k in it.
void segmentEnds(out vec3 Nl, out vec3 Np, out float t) {
    Span sp = spanAt(FRAG_COORD.y);
    float xl, xp;
    int v;
    segmentAt(sp, FRAG_COORD.x, SEGMENT_K, xl, xp, v);
    Nl = segmentEnd(sp, xl);
    Np = segmentEnd(sp, xp);
    t = float(v) / float(1 << SEGMENT_K);
}

#ifdef INV_ROOT
vec3 methodNormal() {
    vec3 Nl, Np;
    float t;
    segmentEnds(Nl, Np, t);
    return dichotomy(Nl, Np, t, SEGMENT_K);
}
#else
#define METHOD_COLOR
vec3 methodColor() {
    vec3 Nl, Np;
    float t;
    segmentEnds(Nl, Np, t);
    return mix(shade(Nl), shade(Np), t);
}
#endif
