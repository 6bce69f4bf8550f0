// quadratic_scanline (docs/formulas.md#quadratic-interpolation-along-the-span): quadratic
// interpolation along the span with the exact middle normal normalize(N'_l + N'_p) (the angular
// midpoint of the unit ends).
#define MIDDLE(Nl, Np) normalize((Nl) + (Np))
#include "quadratic.glsl"
