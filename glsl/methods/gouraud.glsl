// gouraud (docs/formulas.md#gouraud-shading): lit at the vertices (glsl/shade.vert), the colour
// interpolated linearly. No per-pixel normal.
#define METHOD_COLOR
real3 methodColor() {
    return R3(vColor);
}
