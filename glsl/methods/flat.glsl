// flat (FORMULAS.md 2.1, S002 l.43-55, S004 l.18-24): one unit normal per triangle. With
// directional light and the viewer at infinity the whole triangle gets one colour.
real3 methodNormal() {
    return R3(vFlat);
}
