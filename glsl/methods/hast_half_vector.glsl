// hast_half_vector (docs/formulas.md#hast-barrera-bengtsson-half-vector): reflect the flat normal n
// about H = n + N, N' = 2 H (H.n)/(H.H) - n: unit length exactly, no square root, one division.
real3 methodNormal() {
    real3 H = R3(vFlat) + R3(vNormal);
    return R(2.0) * H * (dot(H, R3(vFlat)) / dot(H, H)) - R3(vFlat);
}
