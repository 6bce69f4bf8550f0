// hast_euler (docs/formulas.md#hast-euler-integration; A. Hast, a reconstruction: the survey has
// prose only): each cosine I(t) = v.N(t)/|N(t)| along the span (N(t) = N_A + t (N_B - N_A), the
// Phong edge normals; v = L, and H likewise) integrated by Euler's method in pixel steps h = 1/W
// with the derivative interpolated linearly between its values at the span ends, in closed form
// I_j = I(0) + h (j d0 + (d1 - d0) j (j - 1) / (2W)), then the end error E = I(1) - I_W spread
// over the span: I_j + E j / W. Twin: src/method/scanline.rs euler_cosine().
#define METHOD_COLOR
#define METHOD_COSINE
#include "scanline.glsl"

Span heSpan;
real heT;

// dI/dt of v.N/|N| at N with dN/dt = D.
real heSlope(real3 v, real3 N, real3 D) {
    real n2 = dot(N, N);
    real n = sqrt(n2);
    return dot(v, D) / n - dot(v, N) * dot(N, D) / (n2 * n);
}

real methodCosine(real3 v) {
    real3 NA = heSpan.NA;
    real3 NB = heSpan.NB;
    real W = R(heSpan.xB - heSpan.xA);
    real I0 = dot(v, NA) / length(NA);
    if (!(W > R(0.0))) {
        return I0;
    }
    real I1 = dot(v, NB) / length(NB);
    real3 D = NB - NA;
    real d0 = heSlope(v, NA, D);
    real d1 = heSlope(v, NB, D);
    real h = R(1.0) / W;
    real j = heT * W;
    real Ij = I0 + h * (j * d0 + (d1 - d0) * j * (j - R(1.0)) / (R(2.0) * W));
    real IW = I0 + h * (W * d0 + (d1 - d0) * (W - R(1.0)) / R(2.0));
    return Ij + (I1 - IW) * j / W;
}

real3 methodColor() {
    heSpan = spanAt(FRAG_COORD.y);
    heT = spanT(heSpan, FRAG_COORD.x);
    return shadeCosines();
}
