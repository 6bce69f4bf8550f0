#ifndef QUATERNION_GLSL
#define QUATERNION_GLSL
// Quaternion helpers (FORMULAS.md 2.14), shared by the vertex and fragment stages.
// The unit quaternion turning +Z onto unit n without twist, stored as (x, y, z):
//   z = sqrt((n.z + 1)/2), x = n.x/(2z), y = n.y/(2z)
vec3 quatFromNormal(vec3 n) {
    float z = sqrt(0.5 * (n.z + 1.0));
    return vec3(n.x / (2.0 * z), n.y / (2.0 * z), z);
}
// The normal of an interpolated (non-unit) quaternion: the square root cancels (S000 l.183-203).
vec3 normalFromQuat(vec3 q) {
    return vec3(2.0 * q.x * q.z, 2.0 * q.y * q.z, q.z * q.z - q.x * q.x - q.y * q.y) / dot(q, q);
}
// Orthonormal basis (t, b) completing unit n to a right-handed frame: Duff et al., "Building an
// Orthonormal Basis, Revisited", JCGT 2017 (branchless). Twin: formulas::onb.
void onb(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float b0 = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * b0, -s * n.x);
    b = vec3(b0, s + n.y * n.y * a, -n.y);
}
#endif
