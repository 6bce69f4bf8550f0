// mikami_quadratic (docs/formulas.md#mikami-square-root): first iteration of Mikami's nonlinear IIR
// square root, quadratic beta = 0.763 z^2 - 1.57 z + 1.31: s0 = 2/3 z + 0.35,
// s1 = beta (z - s0^2) + s0 ~ sqrt(z), N' = N / s1.
real3 methodNormal() {
    real z = dot(R3(vNormal), R3(vNormal));
    real s0 = R(2.0 / 3.0) * z + R(0.35);
    real beta = (R(0.763) * z - R(1.57)) * z + R(1.31);
    return R3(vNormal) / (beta * (z - s0 * s0) + s0);
}
