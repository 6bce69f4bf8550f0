// quaternion (docs/formulas.md#quaternion-interpolation): per-vertex quaternions in view space
// (computed in glsl/shade.vert), interpolated, turned back into a unit normal without a square
// root.
#include "quaternion.glsl"
real3 methodNormal() {
    return normalFromQuat(R3(vQuat));
}
