// lyon_shift (FORMULAS.md 2.6, S000 l.52-53): the shift-friendly form, 3/8 replaced by 1/2.
vec3 methodNormal() {
    float e = 1.0 - dot(vNormal, vNormal);
    return vNormal * (1.0 + 0.5 * (e + e * e));
}
