// mikami_linear (docs/formulas.md#mikami-square-root): first iteration of Mikami's nonlinear IIR
// square root, linear beta = 1.07 - 0.62 z: s0 = 2/3 z + 0.35, s1 = beta (z - s0^2) + s0 ~ sqrt(z),
// N' = N / s1.
real3 methodNormal() {
    real z = dot(R3(vNormal), R3(vNormal));
    real s0 = R(2.0 / 3.0) * z + R(0.35);
    real beta = R(1.07) - R(0.62) * z;
    return R3(vNormal) / (beta * (z - s0 * s0) + s0);
}
