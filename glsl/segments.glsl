// Digital segments of 2^SEGMENT_K pixels (docs/formulas.md#digital-segments): exact Phong at the
// segment ends (normalised span normals, the last segment's far end extrapolated past the span as
// the paper says); inside, the colour interpolated linearly (no INV_ROOT), or, with INV_ROOT, the
// normal by dichotomy between the unit end normals (docs/formulas.md#dichotomy-inside-segments).
// Twin: src/method/twins.rs segments().
#include "scanline.glsl"

real3 segmentEnd(Span sp, pix x) {
    real3 N = spanNormal(sp, x);
    return normalize(dot(N, N) > R(1e-12) ? N : sp.NA);   // an extrapolated end can pass through 0
}

// The unit normals at the ends of the fragment's segment and its place t = v / 2^k in it.
void segmentEnds(out real3 Nl, out real3 Np, out real t) {
    Span sp = spanAt(FRAG_COORD.y);
    pix xl, xp;
    int v;
    segmentAt(sp, FRAG_COORD.x, SEGMENT_K, xl, xp, v);
    Nl = segmentEnd(sp, xl);
    Np = segmentEnd(sp, xp);
    t = real(v) / real(1 << SEGMENT_K);
}

#ifdef INV_ROOT
real3 methodNormal() {
    real3 Nl, Np;
    real t;
    segmentEnds(Nl, Np, t);
    return dichotomy(Nl, Np, pix(t), SEGMENT_K);   // t = v / 2^k: exact in both precisions
}
#else
#define METHOD_COLOR
real3 methodColor() {
    real3 Nl, Np;
    real t;
    segmentEnds(Nl, Np, t);
    return mix(shade(Nl), shade(Np), t);
}
#endif
