// Shared declarations for every shadelab shader. Compiled with defines from src/shaders.rs:
//   STAGE_VERTEX / STAGE_FRAGMENT   which stage this is; STAGE_COMPUTE: glsl/evaluate.comp, where
//                                   the varyings and `params` are plain globals set per case
//   INTERP                          noperspective (screen-linear, the seeds' scanline model) or smooth
//   ATTR_*                          vertex streams the program reads (src/render.rs uploads only these)
//   IN_*                            varyings the program needs (only those are declared)
//   USE_LUT                         the specular lookup table (binding 1)
//   SHADELAB_F16                    the float16 variant (program names `<method>.f16.<interp>`,
//                                   `<method>.f16.evaluate`): `real` is float16_t
// The Rust twin of `Params` is `render::Params` (#[repr(C)]); a test compares member offsets
// parsed from the SPIR-V with the Rust offsets.

// Precision-generic vocabulary (issue 23). Every method file and the files it includes are written
// once in it; the float32 programs compile to the same SPIR-V as plain GLSL (the macros expand to
// `float` and to bare parentheses), the float16 programs compute the method and the lighting in
// float16_t (GL_EXT_shader_explicit_arithmetic_types_float16), as a mediump shader on a mobile GPU
// would. Rules for a method file (tests/shaders.rs checks the float16 SPIR-V against them):
//   1. Values are `real`, `real2`, `real3`, `real4`; never `float` or `vecN`.
//   2. Every float literal in real arithmetic is written R(literal): R(0.5), R(2.0 / 3.0). GLSL has
//      no implicit narrowing: a bare literal promotes the float16 expression to float32.
//   3. Inputs (varyings vNormal, vBary, vN0.., params.*, lut[]) are float32: convert them where the
//      method reads them, R(x) for a scalar, R2/R3/R4(x) for a vector: R3(vNormal),
//      R3(params.lightDir[i].xyz). Never compute on them in float32 first.
//   4. Window-space positions (gl_FragCoord through FRAG_COORD, vW0..vW2, span ends x) are `pix`,
//      `pix2`: float32 in both variants, as GLSL ES keeps gl_FragCoord highp; a ratio of positions
//      (a span fraction t) is converted with R() once computed.
//   5. Constructors convert: real3(0.0), real(i) (an int) are fine.
//   6. Results leave as float32 through F(x), F3(x), F4(x) (glsl/method_main.glsl does it).
//   7. A constant that only makes sense at one precision (a threshold below float16's range) is
//      BY_PRECISION(f32 value, f16 value).
#ifdef SHADELAB_F16
#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require
#define real float16_t
#define real2 f16vec2
#define real3 f16vec3
#define real4 f16vec4
#define R(x) float16_t(x)
#define R2(x) f16vec2(x)
#define R3(x) f16vec3(x)
#define R4(x) f16vec4(x)
#define F(x) float(x)
#define F3(x) vec3(x)
#define F4(x) vec4(x)
#define BY_PRECISION(f32, f16) (f16)
#else
#define real float
#define real2 vec2
#define real3 vec3
#define real4 vec4
#define R(x) (x)
#define R2(x) (x)
#define R3(x) (x)
#define R4(x) (x)
#define F(x) (x)
#define F3(x) (x)
#define F4(x) (x)
#define BY_PRECISION(f32, f16) (f32)
#endif
#define pix float
#define pix2 vec2

// VARYING(loc, qualifier) declares a varying; in the compute stage it declares a global.
#if defined(STAGE_VERTEX)
#define VARYING(loc, qualifier) layout(location = loc) qualifier out
#elif defined(STAGE_FRAGMENT)
#define VARYING(loc, qualifier) layout(location = loc) qualifier in
#else
#define VARYING(loc, qualifier)
#endif

// The pixel centre in window space: gl_FragCoord, or the case's pixel in the compute stage.
#ifdef STAGE_COMPUTE
vec4 fragCoord;
#define FRAG_COORD fragCoord
#else
#define FRAG_COORD gl_FragCoord
#endif

layout(constant_id = 0) const int LIGHT_COUNT = 1;   // 1..4, a scene-level specialization constant
// false when the scene's k_s is 0: the specular term (a pow per light) is compiled out.
layout(constant_id = 2) const bool HAS_SPECULAR = true;

#ifdef STAGE_COMPUTE
struct ParamsData {
#else
layout(set = 0, binding = 0, std140) uniform Params {
#endif
    mat4 mvp;            // model -> Vulkan clip space
    vec4 ambient;        // rgb: k_a * I_a
    vec4 diffuse;        // rgb: k_d
    vec4 specular;       // rgb: k_s, w: shininess n
    vec4 lightDir[4];    // view space, unit, from the surface towards the light
    vec4 lightColor[4];  // rgb: I_L
    vec4 halfVec[4];     // normalize(L + V) with the viewer at infinity, V = (0, 0, 1)
    vec4 constColor;     // colour of the constant-colour floor program
#ifdef STAGE_COMPUTE
};
ParamsData params;
#else
} params;
#endif

#ifdef USE_LUT
// cos^n table (docs/formulas.md#specular-table): LUT_ROWS rows (n = 1..LUT_ROWS) of LUT_SAMPLES
// cosines on [0, 1].
layout(set = 0, binding = 1, std430) readonly buffer SpecularLut { float lut[]; };
const int LUT_ROWS = 255;
const int LUT_SAMPLES = 4096;
#endif

#ifdef IN_NORMAL
VARYING(0, INTERP) vec3 vNormal;   // interpolated view-space vertex normal (not unit)
#endif
#ifdef IN_BARY
VARYING(1, INTERP) vec3 vBary;     // interpolation weights of the 3 corners
#endif
#ifdef IN_PRIM
VARYING(2, flat) uint vPrim;       // triangle index (unindexed draw: vertex / 3)
#endif
#ifdef IN_FLAT
VARYING(3, flat) vec3 vFlat;       // unit flat (polygon) normal, oriented like the vertex normals
#endif
#ifdef IN_CORNERS
VARYING(4, flat) vec3 vN0;         // the triangle's three unit vertex normals
VARYING(5, flat) vec3 vN1;
VARYING(6, flat) vec3 vN2;
#endif
#ifdef IN_PN
VARYING(7, flat) vec3 vPn01;       // PN-triangle mid-edge normals n110, n011, n101
VARYING(8, flat) vec3 vPn12;
VARYING(9, flat) vec3 vPn20;
#endif
#ifdef IN_COLOR
VARYING(10, INTERP) vec3 vColor;   // Gouraud: colour lit at the vertices
#endif
#ifdef IN_QUAT
VARYING(11, INTERP) vec3 vQuat;    // quaternion (x, y, z) of the vertex normal
#endif
#ifdef IN_WINDOW
VARYING(12, flat) vec2 vW0;        // the triangle's window-space corners (pixels),
VARYING(13, flat) vec2 vW1;        // set up on the CPU in f64: the scanline
VARYING(14, flat) vec2 vW2;        // methods' span ends (docs/formulas.md#scanline-emulation)
#endif
