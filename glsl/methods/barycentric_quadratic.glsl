// barycentric_quadratic (FORMULAS.md 2.15, S000 l.205-213): the 6-node quadratic triangle whose
// mid-edge nodes are the approximately normalised edge midpoints,
// M_ij = 4 (N_i + N_j)(0.103 c^2 - 0.306 c + 0.705), c = N_i.N_j. Not renormalised.
vec3 mij(vec3 a, vec3 b) {
    float c = dot(a, b);
    return 4.0 * (a + b) * ((0.103 * c - 0.306) * c + 0.705);
}
vec3 methodNormal() {
    vec3 c = vBary;
    return vN0 * (c.x * (2.0 * c.x - 1.0)) + vN1 * (c.y * (2.0 * c.y - 1.0)) + vN2 * (c.z * (2.0 * c.z - 1.0))
         + mij(vN0, vN1) * (c.x * c.y) + mij(vN1, vN2) * (c.y * c.z) + mij(vN2, vN0) * (c.z * c.x);
}
