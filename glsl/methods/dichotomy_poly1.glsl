// dichotomy_poly1 (docs/formulas.md#dichotomy, docs/formulas.md#dichotomy-inside-segments):
// dichotomy (angle halving) between the span's unit end normals, K = ceil(log2(span pixels)) levels
// (1..12), toward the grid point m / 2^K nearest the pixel's t, with the degree-1 inverse root
// 0.64 - 0.07 z. Twin: src/method/scanline.rs dichotomy().
#define INV_ROOT(z) (R(0.64) - R(0.07) * (z))
#include "scanline.glsl"
real3 methodNormal() {
    Span sp = spanAt(FRAG_COORD.y);
    pix t = spanFraction(sp, FRAG_COORD.x);   // a position: the grid index is taken from it
    return dichotomy(normalize(sp.NA), normalize(sp.NB), t, levels(sp.xB - sp.xA));
}
