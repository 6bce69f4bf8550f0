// slerp (docs/formulas.md#slerp): spherical linear interpolation between
// the span's unit end normals N'_A, N'_B (Phong edge normals, normalised exactly) at the pixel's
// fraction t of the span, as the seeds print it: (A sin((1-t) theta) + B sin(t theta)) / sin theta.
// Twin: src/method/scanline.rs slerp().
#include "scanline.glsl"
real3 methodNormal() {
    real3 A, B;
    real t;
    spanEnds(A, B, t);
    real c, s, th;
    if (!angleBetween(A, B, c, s, th)) {
        return normalize(mix(A, B, t));
    }
    return (A * sin((R(1.0) - t) * th) + B * sin(t * th)) / s;
}
