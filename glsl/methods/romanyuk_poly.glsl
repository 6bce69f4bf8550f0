// romanyuk_poly (FORMULAS.md 2.9, S000 l.78-82): k(z) = 0.822 z^2 - 2.046 z + 2.227.
vec3 methodNormal() {
    float z = dot(vNormal, vNormal);
    return vNormal * ((0.822 * z - 2.046) * z + 2.227);
}
