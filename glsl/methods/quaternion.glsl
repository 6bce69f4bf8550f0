// quaternion (FORMULAS.md 2.14, S000 l.183-203): per-vertex quaternions in view space (computed in
// glsl/shade.vert), interpolated, turned back into a unit normal without a square root.
#include "quaternion.glsl"
real3 methodNormal() {
    return normalFromQuat(R3(vQuat));
}
