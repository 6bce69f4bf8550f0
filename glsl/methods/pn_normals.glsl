// pn_normals (docs/formulas.md#pn-triangles-and-trueform; Vlachos et al., "Curved PN Triangles",
// I3D 2001): the quadratic normal field of a PN triangle,
// n = N0 w0^2 + N1 w1^2 + N2 w2^2 + n110 w0 w1 + n011 w1 w2 + n101 w2 w0, evaluated per fragment
// on the flat geometry (mid-edge normals set up on the CPU), normalised.
real3 methodNormal() {
    real3 w = R3(vBary);
    real3 n = R3(vN0) * (w.x * w.x) + R3(vN1) * (w.y * w.y) + R3(vN2) * (w.z * w.z)
           + R3(vPn01) * (w.x * w.y) + R3(vPn12) * (w.y * w.z) + R3(vPn20) * (w.z * w.x);
    return normalize(n);
}
