// Quadratic interpolation along the span (FORMULAS.md 2.12, S000 l.116-152) through the unit end
// normals N'_l (t = 0), N'_p (t = 1) and the middle normal MIDDLE(N'_l, N'_p) (t = 1/2), a macro
// the method file defines: (G t + P) t + N'_l, G = 2N'_p - 4N'_c + 2N'_l, P = 4N'_c - 3N'_l - N'_p
// (the seed swaps l and p in P). Not renormalised. Twin: src/method/scanline.rs quadratic().
#include "scanline.glsl"
vec3 methodNormal() {
    vec3 Nl, Np;
    float t;
    spanEnds(Nl, Np, t);
    vec3 Nc = MIDDLE(Nl, Np);
    vec3 G = 2.0 * Np - 4.0 * Nc + 2.0 * Nl;
    vec3 P = 4.0 * Nc - 3.0 * Nl - Np;
    return (G * t + P) * t + Nl;
}
