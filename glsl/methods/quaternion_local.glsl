// quaternion_local (FORMULAS.md 2.14, recommended variant): quaternions in a per-triangle frame
// whose +Z is the flat normal, so the interpolated normals stay near +Z where the construction is
// accurate; the local normal is turned back to view space with the same frame.
#include "quaternion.glsl"
vec3 methodNormal() {
    vec3 t, b;
    onb(vFlat, t, b);
    vec3 l = normalFromQuat(vQuat);
    return t * l.x + b * l.y + vFlat * l.z;
}
