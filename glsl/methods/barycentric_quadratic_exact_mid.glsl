// barycentric_quadratic_exact_mid (FORMULAS.md 2.15): as barycentric_quadratic, with exact
// mid-edge normals M_ij = 4 normalize(N_i + N_j). Not renormalised.
vec3 mij(vec3 a, vec3 b) {
    return 4.0 * normalize(a + b);
}
vec3 methodNormal() {
    vec3 c = vBary;
    return vN0 * (c.x * (2.0 * c.x - 1.0)) + vN1 * (c.y * (2.0 * c.y - 1.0)) + vN2 * (c.z * (2.0 * c.z - 1.0))
         + mij(vN0, vN1) * (c.x * c.y) + mij(vN1, vN2) * (c.y * c.z) + mij(vN2, vN0) * (c.z * c.x);
}
