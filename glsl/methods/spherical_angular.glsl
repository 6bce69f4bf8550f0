// spherical_angular (docs/formulas.md#spherical-angular-interpolation): spherical-angular
// interpolation in closed form (Gram-Schmidt of N'_B against N'_A), equal to slerp in exact
// arithmetic. The survey's recurrence N(k+1) = 2 cos(phi) N(k) - N(k-1) is sequential along the
// span; a fragment shader evaluates the closed form. Twin: src/method/scanline.rs.
#include "scanline.glsl"
real3 methodNormal() {
    real3 A, B;
    real t;
    spanEnds(A, B, t);
    real c, s, th;
    if (!angleBetween(A, B, c, s, th)) {
        return normalize(mix(A, B, t));
    }
    return A * cos(t * th) + (B - A * c) * (sin(t * th) / s);
}
