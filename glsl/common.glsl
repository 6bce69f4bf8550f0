// Shared declarations for every shadelab shader. Compiled with defines from src/shaders.rs:
//   STAGE_VERTEX / STAGE_FRAGMENT   which stage this is
//   INTERP                          noperspective (screen-linear, the seeds' scanline model) or smooth
//   ATTR_*                          vertex streams the program reads (src/render.rs uploads only these)
//   IN_*                            varyings the program needs (only those are declared)
//   USE_LUT                         the specular lookup table (binding 1)
// The Rust twin of `Params` is `render::Params` (#[repr(C)]); a test compares member offsets
// parsed from the SPIR-V with the Rust offsets.

#ifdef STAGE_VERTEX
#define VARYING out
#else
#define VARYING in
#endif

layout(constant_id = 0) const int LIGHT_COUNT = 1;   // 1..4, a scene-level specialization constant

layout(set = 0, binding = 0, std140) uniform Params {
    mat4 mvp;            // model -> Vulkan clip space
    vec4 ambient;        // rgb: k_a * I_a
    vec4 diffuse;        // rgb: k_d
    vec4 specular;       // rgb: k_s, w: shininess n
    vec4 lightDir[4];    // view space, unit, from the surface towards the light
    vec4 lightColor[4];  // rgb: I_L
    vec4 halfVec[4];     // normalize(L + V) with the viewer at infinity, V = (0, 0, 1)
    vec4 constColor;     // colour of the constant-colour floor program
} params;

#ifdef USE_LUT
// cos^n table (FORMULAS.md 2.20): LUT_ROWS rows (n = 1..LUT_ROWS) of LUT_SAMPLES cosines on [0, 1].
layout(set = 0, binding = 1, std430) readonly buffer SpecularLut { float lut[]; };
const int LUT_ROWS = 255;
const int LUT_SAMPLES = 4096;
#endif

#ifdef IN_NORMAL
layout(location = 0) INTERP VARYING vec3 vNormal;   // interpolated view-space vertex normal (not unit)
#endif
#ifdef IN_BARY
layout(location = 1) INTERP VARYING vec3 vBary;     // interpolation weights of the 3 corners
#endif
#ifdef IN_PRIM
layout(location = 2) flat VARYING uint vPrim;       // triangle index (unindexed draw: vertex / 3)
#endif
#ifdef IN_FLAT
layout(location = 3) flat VARYING vec3 vFlat;       // unit flat (polygon) normal, oriented like the vertex normals
#endif
#ifdef IN_CORNERS
layout(location = 4) flat VARYING vec3 vN0;         // the triangle's three unit vertex normals
layout(location = 5) flat VARYING vec3 vN1;
layout(location = 6) flat VARYING vec3 vN2;
#endif
#ifdef IN_PN
layout(location = 7) flat VARYING vec3 vPn01;       // PN-triangle mid-edge normals n110, n011, n101
layout(location = 8) flat VARYING vec3 vPn12;
layout(location = 9) flat VARYING vec3 vPn20;
#endif
#ifdef IN_COLOR
layout(location = 10) INTERP VARYING vec3 vColor;   // Gouraud: colour lit at the vertices
#endif
#ifdef IN_QUAT
layout(location = 11) INTERP VARYING vec3 vQuat;    // quaternion (x, y, z) of the vertex normal
#endif
#ifdef IN_WINDOW
layout(location = 12) flat VARYING vec2 vW0;        // the triangle's window-space corners (pixels),
layout(location = 13) flat VARYING vec2 vW1;        // set up on the CPU in f64: the scanline
layout(location = 14) flat VARYING vec2 vW2;        // methods' span ends (FORMULAS.md 1.6)
#endif
