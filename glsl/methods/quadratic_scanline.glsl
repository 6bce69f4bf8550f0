// quadratic_scanline (FORMULAS.md 2.12): quadratic interpolation along the span with the exact
// middle normal normalize(N'_l + N'_p) (the angular midpoint of the unit ends).
#define MIDDLE(Nl, Np) normalize((Nl) + (Np))
#include "quadratic.glsl"
