// Quadratic interpolation along the span (docs/formulas.md#quadratic-interpolation-along-the-span)
// through the unit end normals N'_l (t = 0), N'_p (t = 1) and the middle normal MIDDLE(N'_l, N'_p)
// (t = 1/2), a macro the method file defines: (G t + P) t + N'_l, G = 2N'_p - 4N'_c + 2N'_l,
// P = 4N'_c - 3N'_l - N'_p (the survey swaps l and p in P). Not renormalised. Twin:
// src/method/scanline.rs quadratic().
#include "scanline.glsl"
real3 methodNormal() {
    real3 Nl, Np;
    real t;
    spanEnds(Nl, Np, t);
    real3 Nc = MIDDLE(Nl, Np);
    real3 G = R(2.0) * Np - R(4.0) * Nc + R(2.0) * Nl;
    real3 P = R(4.0) * Nc - R(3.0) * Nl - Np;
    return (G * t + P) * t + Nl;
}
