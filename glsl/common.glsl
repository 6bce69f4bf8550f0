// Shared declarations for every shadelab shader. Compiled with defines from src/shaders.rs:
//   STAGE_VERTEX / STAGE_FRAGMENT   which stage this is
//   INTERP                          noperspective (screen-linear, the seeds' scanline model) or smooth
//   IN_NORMAL, IN_BARY, IN_PRIM     which varyings the program needs (only those are declared)
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

#ifdef IN_NORMAL
layout(location = 0) INTERP VARYING vec3 vNormal;   // interpolated view-space vertex normal (not unit)
#endif
#ifdef IN_BARY
layout(location = 1) INTERP VARYING vec3 vBary;     // interpolation weights of the 3 corners
#endif
#ifdef IN_PRIM
layout(location = 2) flat VARYING uint vPrim;       // triangle index (unindexed draw: vertex / 3)
#endif
