// bishop_weimer (FORMULAS.md 2.17, S004 l.106-128; Bishop and Weimer, SIGGRAPH 1986): the Phong
// normal is linear in screen position, N(x, y) = A x + B y + C, fitted to the triangle's window
// corners and unit vertex normals with the origin at the corners' centroid; each cosine
// (v.N)/|N| (v = L, and H "by the same construction") is replaced by its second-order Taylor
// polynomial T5 x^2 + T4 xy + T3 y^2 + T2 x + T1 y + T0 about the origin. Twin:
// src/method/scanline.rs plane_normal() and taylor_cosine().
#define METHOD_COLOR
#define METHOD_COSINE
#include "scanline.glsl"

vec3 bwA;
vec3 bwB;
vec3 bwC;
vec2 bwP;

float methodCosine(vec3 v) {
    float a = dot(v, bwA);
    float b = dot(v, bwB);
    float c = dot(v, bwC);
    float d = dot(bwA, bwA);
    float e = 2.0 * dot(bwA, bwB);
    float f = dot(bwB, bwB);
    float g = 2.0 * dot(bwA, bwC);
    float h = 2.0 * dot(bwB, bwC);
    float i = dot(bwC, bwC);
    float si = sqrt(i);
    float T0 = c / si;
    float T1 = (2.0 * b * i - c * h) / (2.0 * i * si);
    float T2 = (2.0 * a * i - c * g) / (2.0 * i * si);
    float T3 = (3.0 * c * h * h - 4.0 * c * f * i - 4.0 * b * h * i) / (8.0 * i * i * si);
    float T4 = (3.0 * c * g * h - 2.0 * c * e * i - 2.0 * b * g * i - 2.0 * a * h * i) / (4.0 * i * i * si);
    float T5 = (3.0 * c * g * g - 4.0 * c * d * i - 4.0 * a * g * i) / (8.0 * i * i * si);
    float x = bwP.x;
    float y = bwP.y;
    return T5 * x * x + T4 * x * y + T3 * y * y + T2 * x + T1 * y + T0;
}

vec3 methodColor() {
    vec2 o = (vW0 + vW1 + vW2) / 3.0;
    vec2 q0 = vW0 - o;
    vec2 e1 = vW1 - vW0;
    vec2 e2 = vW2 - vW0;
    float det = e1.x * e2.y - e1.y * e2.x;
    if (abs(det) > 1e-12) {
        bwA = ((vN1 - vN0) * e2.y - (vN2 - vN0) * e1.y) / det;
        bwB = ((vN2 - vN0) * e1.x - (vN1 - vN0) * e2.x) / det;
    } else {
        bwA = vec3(0.0);                               // no area on screen: constant normal
        bwB = vec3(0.0);
    }
    bwC = vN0 - bwA * q0.x - bwB * q0.y;
    bwP = FRAG_COORD.xy - o;
    return shadeCosines();
}
