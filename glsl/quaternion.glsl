#ifndef QUATERNION_GLSL
#define QUATERNION_GLSL
// Quaternion helpers (docs/formulas.md#quaternion-interpolation), shared by the vertex and fragment
// stages. The unit quaternion turning +Z onto unit n without twist, stored as (x, y, z):
// z = sqrt((n.z + 1)/2), x = n.x/(2z), y = n.y/(2z)
real3 quatFromNormal(real3 n) {
    real z = sqrt(R(0.5) * (n.z + R(1.0)));
    return real3(n.x / (R(2.0) * z), n.y / (R(2.0) * z), z);
}
// The normal of an interpolated (non-unit) quaternion: the square root cancels
// (docs/formulas.md#quaternion-interpolation).
real3 normalFromQuat(real3 q) {
    return real3(R(2.0) * q.x * q.z, R(2.0) * q.y * q.z, q.z * q.z - q.x * q.x - q.y * q.y) / dot(q, q);
}
// Orthonormal basis (t, b) completing unit n to a right-handed frame: Duff et al., "Building an
// Orthonormal Basis, Revisited", JCGT 2017 (branchless). Twin: formulas::onb.
void onb(real3 n, out real3 t, out real3 b) {
    real s = n.z >= R(0.0) ? R(1.0) : R(-1.0);
    real a = R(-1.0) / (s + n.z);
    real b0 = n.x * n.y * a;
    t = real3(R(1.0) + s * n.x * n.x * a, s * b0, -s * n.x);
    b = real3(b0, s + n.y * n.y * a, -n.y);
}
#endif
