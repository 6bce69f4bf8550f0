// barycentric_quadratic_exact_mid (docs/formulas.md#barycentric-quadratic-triangle): as
// barycentric_quadratic, with exact mid-edge normals M_ij = 4 normalize(N_i + N_j). Not
// renormalised.
real3 mij(real3 a, real3 b) {
    return R(4.0) * normalize(a + b);
}
real3 methodNormal() {
    real3 c = R3(vBary);
    return R3(vN0) * (c.x * (R(2.0) * c.x - R(1.0))) + R3(vN1) * (c.y * (R(2.0) * c.y - R(1.0))) + R3(vN2) * (c.z * (R(2.0) * c.z - R(1.0)))
         + mij(R3(vN0), R3(vN1)) * (c.x * c.y) + mij(R3(vN1), R3(vN2)) * (c.y * c.z) + mij(R3(vN2), R3(vN0)) * (c.z * c.x);
}
