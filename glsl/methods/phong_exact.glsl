// phong_exact (FORMULAS.md 2.3, S002 l.104-150): N' = N / |N|, the reference.
real3 methodNormal() {
    return normalize(R3(vNormal));
}
