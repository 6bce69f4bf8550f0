#version 450
// A method on a buffer of cases (`shadelab stress`, src/gpu/evaluate.rs): each invocation sets
// the inputs the fragment stage would see (the varyings as the vertex stage and the rasterizer
// would produce them from the case's corners and weights, gl_FragCoord, one light) and runs the
// same method code as glsl/shade.frag (glsl/method_main.glsl). Twin of the case layout:
// gpu::evaluate::GpuCase.
#define STAGE_COMPUTE
#include "common.glsl"
#include "shading.glsl"
#ifdef IN_QUAT
#include "quaternion.glsl"
#endif

struct Case {
    vec4 weights;      // xyz: interpolation weights of corners 0, 1, 2
    vec4 pixel;        // xy: the pixel centre in window space
    vec4 window[3];    // xy: the triangle's window-space corners
    vec4 normals[3];   // xyz: vertex normals (unit, or scaled by the stress sweep of lengths)
    vec4 flatNormal;   // xyz: unit flat normal
    vec4 pn[3];        // xyz: PN mid-edge normals n110, n011, n101
    vec4 lightDir;     // xyz: L, unit, towards the light
    vec4 halfVec;      // xyz: H = normalize(L + V)
    vec4 lightColor;   // rgb: I_L
    vec4 ambient;      // rgb: k_a I_a
    vec4 diffuse;      // rgb: k_d
    vec4 specular;     // rgb: k_s, w: shininess
};

layout(set = 0, binding = 0, std430) readonly buffer Cases { Case cases[]; };
// Two per case: (colour, 1) and the shading normal (w 1 = the method has one).
layout(set = 0, binding = 2, std430) writeonly buffer Results { vec4 results[]; };

layout(local_size_x = 64) in;

// Evaluations per invocation (`bench`'s isolated cost; 1 for `stress`). From the second on, each
// reads inputs nudged by the previous colour, a dependency chain the compiler can neither hoist
// nor drop; 0 stores the loaded inputs without evaluating the method (the chain's baseline).
layout(constant_id = 1) const int REPEAT = 1;

#include "method_main.glsl"

// Adds d to every input the method may read (d is ~1e-30 of a colour: no input changes in
// float32, but no compiler can know that).
void nudge(vec3 d) {
    float e = d.x + d.y + d.z;
    fragCoord.xy += vec2(e);
    params.lightDir[0].xyz += d;
    params.halfVec[0].xyz += d;
#ifdef IN_NORMAL
    vNormal += d;
#endif
#ifdef IN_BARY
    vBary += d;
#endif
#ifdef IN_FLAT
    vFlat += d;
#endif
#ifdef IN_CORNERS
    vN0 += d;
    vN1 += d;
    vN2 += d;
#endif
#ifdef IN_WINDOW
    vW0 += vec2(e);
    vW1 += vec2(e);
    vW2 += vec2(e);
#endif
#ifdef IN_PN
    vPn01 += d;
    vPn12 += d;
    vPn20 += d;
#endif
#ifdef IN_COLOR
    vColor += d;
#endif
#ifdef IN_QUAT
    vQuat += d;
#endif
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(cases.length())) {
        return;
    }
    Case c = cases[i];
    params.ambient = c.ambient;
    params.diffuse = c.diffuse;
    params.specular = c.specular;
    params.lightDir[0] = c.lightDir;
    params.lightColor[0] = c.lightColor;
    params.halfVec[0] = c.halfVec;
    fragCoord = vec4(c.pixel.xy, 0.5, 1.0);
    vec3 w = c.weights.xyz;
    vec3 n0 = c.normals[0].xyz;
    vec3 n1 = c.normals[1].xyz;
    vec3 n2 = c.normals[2].xyz;
#ifdef IN_NORMAL
    vNormal = n0 * w.x + n1 * w.y + n2 * w.z;
#endif
#ifdef IN_BARY
    vBary = w;
#endif
#ifdef IN_PRIM
    vPrim = 0u;
#endif
#ifdef IN_FLAT
    vFlat = c.flatNormal.xyz;
#endif
#ifdef IN_CORNERS
    vN0 = n0;
    vN1 = n1;
    vN2 = n2;
#endif
#ifdef IN_WINDOW
    vW0 = c.window[0].xy;
    vW1 = c.window[1].xy;
    vW2 = c.window[2].xy;
#endif
#ifdef IN_PN
    vPn01 = c.pn[0].xyz;
    vPn12 = c.pn[1].xyz;
    vPn20 = c.pn[2].xyz;
#endif
#ifdef IN_COLOR
    vColor = F3(shade(R3(n0))) * w.x + F3(shade(R3(n1))) * w.y + F3(shade(R3(n2))) * w.z;   // as glsl/shade.vert
#endif
#ifdef IN_QUAT
#ifdef QUAT_LOCAL
    real3 t, b, nf = R3(c.flatNormal.xyz);
    onb(nf, t, b);
    vQuat = F3(quatFromNormal(real3(dot(R3(n0), t), dot(R3(n0), b), dot(R3(n0), nf)))) * w.x
          + F3(quatFromNormal(real3(dot(R3(n1), t), dot(R3(n1), b), dot(R3(n1), nf)))) * w.y
          + F3(quatFromNormal(real3(dot(R3(n2), t), dot(R3(n2), b), dot(R3(n2), nf)))) * w.z;
#else
    vQuat = F3(quatFromNormal(R3(n0))) * w.x + F3(quatFromNormal(R3(n1))) * w.y + F3(quatFromNormal(R3(n2))) * w.z;
#endif
#endif
    if (REPEAT == 0) {
        results[2 * i] = vec4(c.weights.xyz + n0 + n1 + n2 + fragCoord.xyz, 1.0);
        results[2 * i + 1] = vec4(0.0);
        return;
    }
    vec3 color;
    vec4 normal;
    evaluateMethod(color, normal);
    vec3 sum = color;
    for (int k = 1; k < REPEAT; ++k) {
        nudge(color * 1e-30);
        evaluateMethod(color, normal);
        sum += color;
    }
    results[2 * i] = vec4(REPEAT == 1 ? color : sum, 1.0);
    results[2 * i + 1] = normal;
}
