// mikami_linear (FORMULAS.md 2.8, S000 l.65-75): first iteration of Mikami's nonlinear IIR square
// root, linear beta = 1.07 - 0.62 z: s0 = 2/3 z + 0.35, s1 = beta (z - s0^2) + s0 ~ sqrt(z), N' = N / s1.
vec3 methodNormal() {
    float z = dot(vNormal, vNormal);
    float s0 = (2.0 / 3.0) * z + 0.35;
    float beta = 1.07 - 0.62 * z;
    return vNormal / (beta * (z - s0 * s0) + s0);
}
