// quaternion_local (docs/formulas.md#quaternion-interpolation, recommended variant): quaternions in
// a per-triangle frame whose +Z is the flat normal, so the interpolated normals stay near +Z where
// the construction is accurate; the local normal is turned back to view space with the same frame.
#include "quaternion.glsl"
real3 methodNormal() {
    real3 t, b;
    onb(R3(vFlat), t, b);
    real3 l = normalFromQuat(R3(vQuat));
    return t * l.x + b * l.y + R3(vFlat) * l.z;
}
