// newton_raphson (docs/formulas.md#newton-raphson-step): one Newton step for 1/sqrt(z)
// from 1: N' = N (3 - z)/2. (The shading survey prints "/3", a typo: k(1) must be 1.)
real3 methodNormal() {
    real z = dot(R3(vNormal), R3(vNormal));
    return R3(vNormal) * (R(0.5) * (R(3.0) - z));
}
