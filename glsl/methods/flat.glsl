// flat (docs/formulas.md#flat-shading): one unit normal per triangle. With
// directional light and the viewer at infinity the whole triangle gets one colour.
real3 methodNormal() {
    return R3(vFlat);
}
