// romanyuk_poly (docs/formulas.md#romanyuk-romanyuk-pavlyk-polynomial):
// k(z) = 0.822 z^2 - 2.046 z + 2.227.
real3 methodNormal() {
    real z = dot(R3(vNormal), R3(vNormal));
    return R3(vNormal) * ((R(0.822) * z - R(2.046)) * z + R(2.227));
}
