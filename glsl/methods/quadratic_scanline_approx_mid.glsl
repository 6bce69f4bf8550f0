// quadratic_scanline_approx_mid (docs/formulas.md#quadratic-interpolation-along-the-span):
// quadratic interpolation along the span with the approximate middle normal
// (0.103 c^2 - 0.306 c + 0.705)(N'_l + N'_p), c = N'_l.N'_p.
#define MIDDLE(Nl, Np) (((R(0.103) * dot(Nl, Np) - R(0.306)) * dot(Nl, Np) + R(0.705)) * ((Nl) + (Np)))
#include "quadratic.glsl"
