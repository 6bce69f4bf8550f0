// phong_exact (docs/formulas.md#exact-phong): N' = N / |N|, the reference.
real3 methodNormal() {
    return normalize(R3(vNormal));
}
