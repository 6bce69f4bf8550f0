// lyon_taylor (docs/formulas.md#lyon-taylor-form): 2nd-degree Taylor series of z^(-1/2) about 1.
real3 methodNormal() {
    real d = dot(R3(vNormal), R3(vNormal)) - R(1.0);
    return R3(vNormal) * (R(1.0) - R(0.5) * d + R(0.375) * d * d);
}
