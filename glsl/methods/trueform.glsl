// trueform (docs/formulas.md#pn-triangles-and-trueform): ATI TrueForm as the shading survey
// describes it: every triangle replaced by 9 sub-triangles of its PN patch (tessellation level 3,
// on the CPU), lit at the sub-vertices with the PN normals, Gouraud in between. No per-pixel
// normal.
#define METHOD_COLOR
real3 methodColor() {
    return R3(vColor);
}
