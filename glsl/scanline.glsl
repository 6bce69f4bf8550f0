// Scanline emulation in a fragment shader (FORMULAS.md 1.6): the span through the fragment's
// row, from the triangle's window-space corners (vW0..vW2) and unit vertex normals (vN0..vN2),
// both flat varyings set up on the CPU. Twin: src/method/scanline.rs (same branches).
// These methods depend on the scanline direction: they are not rotation-invariant on screen.
struct Span {
    float xA;
    vec3 NA;   // Phong edge normal at xA (linear along the edge, not unit)
    float xB;
    vec3 NB;
};

Span spanAt(float py) {
    vec2 s[3] = vec2[3](vW0, vW1, vW2);
    vec3 nv[3] = vec3[3](vN0, vN1, vN2);
    // Clamp to the triangle's rows: a covered pixel on the top or bottom row still finds edges.
    py = clamp(py, min(s[0].y, min(s[1].y, s[2].y)), max(s[0].y, max(s[1].y, s[2].y)));
    Span sp = Span(1e30, nv[0], -1e30, nv[0]);
    for (int e = 0; e < 3; ++e) {
        vec2 p = s[e];
        vec2 q = s[(e + 1) % 3];
        if (p.y == q.y) {
            continue;                                   // horizontal edge
        }
        float u = (py - p.y) / (q.y - p.y);
        if (u < 0.0 || u > 1.0) {
            continue;
        }
        float x = p.x * (1.0 - u) + q.x * u;
        vec3 N = nv[e] * (1.0 - u) + nv[(e + 1) % 3] * u;
        if (x < sp.xA) {
            sp.xA = x;
            sp.NA = N;
        }
        if (x > sp.xB) {
            sp.xB = x;
            sp.NB = N;
        }
    }
    if (sp.xA > sp.xB) {                                // all corners on one row
        sp.xA = s[0].x;
        sp.xB = s[0].x;
    }
    return sp;
}

// The angle theta in [0, pi] with cos(theta) = c, sin(theta) = s >= 0, to float32 rounding:
// Mesa's acos is a low-degree polynomial (off by up to ~1.5e-4 rad on lavapipe), so one step
// theta += sin(theta - theta0) = s cos(theta0) - c sin(theta0) refines it (sin and cos are
// accurate there). The f64 twin takes acos(c) exactly.
float angleOf(float c, float s) {
    float t0 = acos(c);
    return t0 + (s * cos(t0) - c * sin(t0));
}

// Where the pixel lies on the span, in [0, 1]; 0 on an empty span.
float spanT(Span sp, float px) {
    return sp.xB > sp.xA ? clamp((px - sp.xA) / (sp.xB - sp.xA), 0.0, 1.0) : 0.0;
}

// The span's unit end normals N'_A, N'_B (exact normalisation, as the seeds assume) and the
// fragment's fraction t of the span.
void spanEnds(out vec3 A, out vec3 B, out float t) {
    Span sp = spanAt(FRAG_COORD.y);
    t = spanT(sp, FRAG_COORD.x);
    A = normalize(sp.NA);
    B = normalize(sp.NB);
}

// Below this 1 - c^2 (angle under 1e-4 rad) the angle-based interpolations use normalize(mix).
const float PARALLEL = 1e-8;

// The angle between unit A and B: its cosine c, sine s and the angle th (acos refined);
// false within PARALLEL of parallel or antipodal, where the callers use normalize(mix).
bool angleBetween(vec3 A, vec3 B, out float c, out float s, out float th) {
    c = clamp(dot(A, B), -1.0, 1.0);
    float s2 = 1.0 - c * c;
    if (s2 < PARALLEL) {
        return false;
    }
    s = sqrt(s2);
    th = angleOf(c, s);
    return true;
}

// The Phong normal of the span at x: linear in x, extrapolated past the ends.
vec3 spanNormal(Span sp, float x) {
    return sp.xB > sp.xA ? sp.NA + (sp.NB - sp.NA) * ((x - sp.xA) / (sp.xB - sp.xA)) : sp.NA;
}

// Halving levels for a span of `width` pixels: the least k >= 1 with 2^k >= width, at most 12.
const int MAX_LEVELS = 12;
int levels(float width) {
    int k = 1;
    while (k < MAX_LEVELS && float(1 << k) < width) {
        ++k;
    }
    return k;
}

#ifdef INV_ROOT
// Dichotomy (FORMULAS.md 2.13): the slerp sample nearest t on the grid m / 2^K, by K bisections
// with mid = (lo + hi) INV_ROOT(2 lo.hi); m = floor(t 2^K + 0.5).
vec3 dichotomy(vec3 A, vec3 B, float t, int K) {
    int n = 1 << K;
    int m = min(int(floor(t * float(n) + 0.5)), n);
    if (m == 0) {
        return A;
    }
    if (m == n) {
        return B;
    }
    vec3 lo = A;
    vec3 hi = B;
    for (int l = 0; l < K; ++l) {
        vec3 mid = (lo + hi) * INV_ROOT(2.0 * dot(lo, hi));
        if (((m >> (K - 1 - l)) & 1) != 0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}
#endif

// The digital segment of 2^k pixels holding the pixel (FORMULAS.md 2.16): its end positions
// xl, xp (pixel centres; the first starts at the first covered pixel centre) and the pixel's
// index v in it.
void segmentAt(Span sp, float px, int k, out float xl, out float xp, out int v) {
    float p0 = ceil(sp.xA - 0.5) + 0.5;
    int j = max(int(floor(px - p0)), 0);
    xl = p0 + float((j >> k) << k);
    xp = xl + float(1 << k);
    v = j & ((1 << k) - 1);
}

#ifdef METHOD_COSINE
// The lighting model of glsl/shading.glsl from the cosines alone, for methods that approximate
// N.L and N.H rather than N (Bishop-Weimer, Hast-Euler): methodCosine(v) is the method's N.v.
// Twin: Lighting::shade_cosines in src/method/formulas.rs.
float methodCosine(vec3 v);
vec3 shadeCosines() {
    vec3 c = params.ambient.rgb;
    for (int i = 0; i < LIGHT_COUNT; ++i) {
        float d = max(methodCosine(params.lightDir[i].xyz), 0.0);
        float s = max(methodCosine(params.halfVec[i].xyz), 0.0);
        float sp = HAS_SPECULAR && s > 0.0 ? pow(s, params.specular.w) : 0.0;
        c += params.lightColor[i].rgb * (params.diffuse.rgb * d + params.specular.rgb * sp);
    }
    return c;
}
#endif
