// hast_half_vector (FORMULAS.md 2.7, S000 l.55-63): reflect the flat normal n about H = n + N,
// N' = 2 H (H.n)/(H.H) - n: unit length exactly, no square root, one division.
vec3 methodNormal() {
    vec3 H = vFlat + vNormal;
    return 2.0 * H * (dot(H, vFlat) / dot(H, H)) - vFlat;
}
