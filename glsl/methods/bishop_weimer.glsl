// bishop_weimer (docs/formulas.md#bishop-weimer-taylor-shading; Bishop and Weimer, SIGGRAPH 1986):
// the Phong normal is linear in screen position, N(x, y) = A x + B y + C, fitted to the triangle's
// window corners and unit vertex normals with the origin at the corners' centroid; each cosine
// (v.N)/|N| (v = L, and H "by the same construction") is replaced by its second-order Taylor
// polynomial T5 x^2 + T4 xy + T3 y^2 + T2 x + T1 y + T0 about the origin. Twin:
// src/method/scanline.rs plane_normal() and taylor_cosine().
#define METHOD_COLOR
#define METHOD_COSINE
#include "scanline.glsl"

real3 bwA;
real3 bwB;
real3 bwC;
real2 bwP;

real methodCosine(real3 v) {
    real a = dot(v, bwA);
    real b = dot(v, bwB);
    real c = dot(v, bwC);
    real d = dot(bwA, bwA);
    real e = R(2.0) * dot(bwA, bwB);
    real f = dot(bwB, bwB);
    real g = R(2.0) * dot(bwA, bwC);
    real h = R(2.0) * dot(bwB, bwC);
    real i = dot(bwC, bwC);
    real si = sqrt(i);
    real T0 = c / si;
    real T1 = (R(2.0) * b * i - c * h) / (R(2.0) * i * si);
    real T2 = (R(2.0) * a * i - c * g) / (R(2.0) * i * si);
    real T3 = (R(3.0) * c * h * h - R(4.0) * c * f * i - R(4.0) * b * h * i) / (R(8.0) * i * i * si);
    real T4 = (R(3.0) * c * g * h - R(2.0) * c * e * i - R(2.0) * b * g * i - R(2.0) * a * h * i) / (R(4.0) * i * i * si);
    real T5 = (R(3.0) * c * g * g - R(4.0) * c * d * i - R(4.0) * a * g * i) / (R(8.0) * i * i * si);
    real x = bwP.x;
    real y = bwP.y;
    return T5 * x * x + T4 * x * y + T3 * y * y + T2 * x + T1 * y + T0;
}

real3 methodColor() {
    pix2 o = (vW0 + vW1 + vW2) / 3.0;
    pix2 q0 = vW0 - o;
    pix2 e1 = vW1 - vW0;
    pix2 e2 = vW2 - vW0;
    pix det = e1.x * e2.y - e1.y * e2.x;
    // The plane's gradients A, B are triangle setup (positions, pixels^2 in det): float32 in both
    // precisions, converted once; the rest of the method is in `real`.
    if (abs(det) > 1e-12) {
        bwA = R3(((vN1 - vN0) * e2.y - (vN2 - vN0) * e1.y) / det);
        bwB = R3(((vN2 - vN0) * e1.x - (vN1 - vN0) * e2.x) / det);
    } else {
        bwA = real3(0.0);                              // no area on screen: constant normal
        bwB = real3(0.0);
    }
    bwC = R3(vN0) - bwA * R(q0.x) - bwB * R(q0.y);
    bwP = R2(FRAG_COORD.xy - o);
    return shadeCosines();
}
