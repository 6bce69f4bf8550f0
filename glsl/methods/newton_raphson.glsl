// newton_raphson (FORMULAS.md 2.4, S000 l.33-38, S004 l.167-172): one Newton step for 1/sqrt(z)
// from 1: N' = N (3 - z)/2. (S004 prints "/3", a typo: k(1) must be 1.)
real3 methodNormal() {
    real z = dot(R3(vNormal), R3(vNormal));
    return R3(vNormal) * (R(0.5) * (R(3.0) - z));
}
