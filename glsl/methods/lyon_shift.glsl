// lyon_shift (docs/formulas.md#lyon-shift-form): the shift-friendly form, 3/8 replaced by 1/2.
real3 methodNormal() {
    real e = R(1.0) - dot(R3(vNormal), R3(vNormal));
    return R3(vNormal) * (R(1.0) + R(0.5) * (e + e * e));
}
