// lyon_taylor (FORMULAS.md 2.5, S000 l.45-50): 2nd-degree Taylor series of z^(-1/2) about 1.
vec3 methodNormal() {
    float d = dot(vNormal, vNormal) - 1.0;
    return vNormal * (1.0 - 0.5 * d + 0.375 * d * d);
}
