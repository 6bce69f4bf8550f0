// dichotomy_poly2 (docs/formulas.md#dichotomy, docs/formulas.md#dichotomy-inside-segments):
// dichotomy (angle halving) between the span's unit end normals, K = ceil(log2(span pixels)) levels
// (1..12), toward the grid point m / 2^K nearest the pixel's t, with the degree-2 minimax inverse
// root 0.014253 z^2 - 0.118922 z + 0.680850. Twin: src/method/scanline.rs dichotomy().
#define INV_ROOT(z) ((R(0.014253) * (z) - R(0.118922)) * (z) + R(0.680850))
#include "scanline.glsl"
real3 methodNormal() {
    Span sp = spanAt(FRAG_COORD.y);
    pix t = spanFraction(sp, FRAG_COORD.x);   // a position: the grid index is taken from it
    return dichotomy(normalize(sp.NA), normalize(sp.NB), t, levels(sp.xB - sp.xA));
}
