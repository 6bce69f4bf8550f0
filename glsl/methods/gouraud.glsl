// gouraud (FORMULAS.md 2.2, S002 l.57-102): lit at the vertices (glsl/shade.vert), the colour
// interpolated linearly. No per-pixel normal.
#define METHOD_COLOR
real3 methodColor() {
    return R3(vColor);
}
