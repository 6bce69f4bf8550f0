// hast_euler (FORMULAS.md 2.18, S004 l.130-140; A. Hast, a reconstruction: the seed has prose
// only): each cosine I(t) = v.N(t)/|N(t)| along the span (N(t) = N_A + t (N_B - N_A), the Phong
// edge normals; v = L, and H likewise) integrated by Euler's method in pixel steps h = 1/W with
// the derivative interpolated linearly between its values at the span ends, in closed form
// I_j = I(0) + h (j d0 + (d1 - d0) j (j - 1) / (2W)), then the end error E = I(1) - I_W spread
// over the span: I_j + E j / W. Twin: src/method/scanline.rs euler_cosine().
#define METHOD_COLOR
#define METHOD_COSINE
#include "scanline.glsl"

Span heSpan;
float heT;

// dI/dt of v.N/|N| at N with dN/dt = D.
float heSlope(vec3 v, vec3 N, vec3 D) {
    float n2 = dot(N, N);
    float n = sqrt(n2);
    return dot(v, D) / n - dot(v, N) * dot(N, D) / (n2 * n);
}

float methodCosine(vec3 v) {
    vec3 NA = heSpan.NA;
    vec3 NB = heSpan.NB;
    float W = heSpan.xB - heSpan.xA;
    float I0 = dot(v, NA) / length(NA);
    if (!(W > 0.0)) {
        return I0;
    }
    float I1 = dot(v, NB) / length(NB);
    vec3 D = NB - NA;
    float d0 = heSlope(v, NA, D);
    float d1 = heSlope(v, NB, D);
    float h = 1.0 / W;
    float j = heT * W;
    float Ij = I0 + h * (j * d0 + (d1 - d0) * j * (j - 1.0) / (2.0 * W));
    float IW = I0 + h * (W * d0 + (d1 - d0) * (W - 1.0) / 2.0);
    return Ij + (I1 - IW) * j / W;
}

vec3 methodColor() {
    heSpan = spanAt(FRAG_COORD.y);
    heT = spanT(heSpan, FRAG_COORD.x);
    return shadeCosines();
}
