// quadratic_scanline_approx_mid (FORMULAS.md 2.12, S000 l.116-152): quadratic interpolation along the span through the
// unit end normals N'_l (t = 0), N'_p (t = 1) and the middle normal N'_c (t = 1/2), here
// the approximate middle normal (0.103 c^2 - 0.306 c + 0.705)(N'_l + N'_p), c = N'_l.N'_p:
// (G t + P) t + N'_l, G = 2N'_p - 4N'_c + 2N'_l, P = 4N'_c - 3N'_l - N'_p (the seed swaps l and p
// in P). Not renormalised. Twin: src/method/scanline.rs quadratic().
#include "scanline.glsl"
vec3 methodNormal() {
    Span sp = spanAt(gl_FragCoord.y);
    float t = spanT(sp, gl_FragCoord.x);
    vec3 Nl = normalize(sp.NA);
    vec3 Np = normalize(sp.NB);
    float c = dot(Nl, Np);
    vec3 Nc = ((0.103 * c - 0.306) * c + 0.705) * (Nl + Np);
    vec3 G = 2.0 * Np - 4.0 * Nc + 2.0 * Nl;
    vec3 P = 4.0 * Nc - 3.0 * Nl - Np;
    return (G * t + P) * t + Nl;
}
