// barycentric_quadratic (docs/formulas.md#barycentric-quadratic-triangle): the 6-node quadratic
// triangle whose mid-edge nodes are the approximately normalised edge midpoints, 
// M_ij = 4 (N_i + N_j)(0.103 c^2 - 0.306 c + 0.705), c = N_i.N_j. Not renormalised.
real3 mij(real3 a, real3 b) {
    real c = dot(a, b);
    return R(4.0) * (a + b) * ((R(0.103) * c - R(0.306)) * c + R(0.705));
}
real3 methodNormal() {
    real3 c = R3(vBary);
    return R3(vN0) * (c.x * (R(2.0) * c.x - R(1.0))) + R3(vN1) * (c.y * (R(2.0) * c.y - R(1.0))) + R3(vN2) * (c.z * (R(2.0) * c.z - R(1.0)))
         + mij(R3(vN0), R3(vN1)) * (c.x * c.y) + mij(R3(vN1), R3(vN2)) * (c.y * c.z) + mij(R3(vN2), R3(vN0)) * (c.z * c.x);
}
