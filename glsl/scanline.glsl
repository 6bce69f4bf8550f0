// Scanline emulation in a fragment shader (docs/formulas.md#scanline-emulation): the span through
// the fragment's row, from the triangle's window-space corners (vW0..vW2) and unit vertex normals
// (vN0..vN2), both flat varyings set up on the CPU. Twin: src/method/scanline.rs (same branches).
// These methods depend on the scanline direction: they are not rotation-invariant on screen.
// Positions are `pix` (float32 in both precisions), normals `real` (glsl/common.glsl).
struct Span {
    pix xA;
    real3 NA;   // Phong edge normal at xA (linear along the edge, not unit)
    pix xB;
    real3 NB;
};

Span spanAt(pix py) {
    pix2 s[3] = pix2[3](vW0, vW1, vW2);
    real3 nv[3] = real3[3](R3(vN0), R3(vN1), R3(vN2));
    // Clamp to the triangle's rows: a covered pixel on the top or bottom row still finds edges.
    py = clamp(py, min(s[0].y, min(s[1].y, s[2].y)), max(s[0].y, max(s[1].y, s[2].y)));
    Span sp = Span(1e30, nv[0], -1e30, nv[0]);
    for (int e = 0; e < 3; ++e) {
        pix2 p = s[e];
        pix2 q = s[(e + 1) % 3];
        if (p.y == q.y) {
            continue;                                   // horizontal edge
        }
        pix u = (py - p.y) / (q.y - p.y);
        if (u < 0.0 || u > 1.0) {
            continue;
        }
        pix x = p.x * (1.0 - u) + q.x * u;
        real3 N = nv[e] * R(1.0 - u) + nv[(e + 1) % 3] * R(u);
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
real angleOf(real c, real s) {
    real t0 = acos(c);
    return t0 + (s * cos(t0) - c * sin(t0));
}

// Where the pixel lies on the span, in [0, 1]; 0 on an empty span.
real spanT(Span sp, pix px) {
    return sp.xB > sp.xA ? R(clamp((px - sp.xA) / (sp.xB - sp.xA), 0.0, 1.0)) : R(0.0);
}

// spanT kept as a position (float32 in both precisions, rule 4): for a decision on the pixel's
// place in the span, such as dichotomy's grid index, taken before any conversion to `real`.
pix spanFraction(Span sp, pix px) {
    return sp.xB > sp.xA ? clamp((px - sp.xA) / (sp.xB - sp.xA), 0.0, 1.0) : 0.0;
}

// The span's unit end normals N'_A, N'_B (exact normalisation, as the seeds assume) and the
// fragment's fraction t of the span.
void spanEnds(out real3 A, out real3 B, out real t) {
    Span sp = spanAt(FRAG_COORD.y);
    t = spanT(sp, FRAG_COORD.x);
    A = normalize(sp.NA);
    B = normalize(sp.NB);
}

// Below this 1 - c^2 (angle under 1e-4 rad) the angle-based interpolations use normalize(mix).
// float16: 2^-9 = 4u (angle under 0.044 rad): 1e-8 is below float16's smallest subnormal, and
// 1 - c^2 carries an error of a few u, so a smaller threshold divides by noise.
const real PARALLEL = R(BY_PRECISION(1e-8, 0.001953125));

// The angle between unit A and B: its cosine c, sine s and the angle th (acos refined);
// false within PARALLEL of parallel or antipodal, where the callers use normalize(mix).
bool angleBetween(real3 A, real3 B, out real c, out real s, out real th) {
    c = clamp(dot(A, B), R(-1.0), R(1.0));
    real s2 = R(1.0) - c * c;
    if (s2 < PARALLEL) {
        return false;
    }
    s = sqrt(s2);
    th = angleOf(c, s);
    return true;
}

// The Phong normal of the span at x: linear in x, extrapolated past the ends.
real3 spanNormal(Span sp, pix x) {
    return sp.xB > sp.xA ? sp.NA + (sp.NB - sp.NA) * R((x - sp.xA) / (sp.xB - sp.xA)) : sp.NA;
}

// Halving levels for a span of `width` pixels: the least k >= 1 with 2^k >= width, at most 12.
const int MAX_LEVELS = 12;
int levels(pix width) {
    int k = 1;
    while (k < MAX_LEVELS && pix(1 << k) < width) {
        ++k;
    }
    return k;
}

#ifdef INV_ROOT
// Dichotomy (docs/formulas.md#dichotomy): the slerp sample nearest t on the grid m / 2^K, by K
// bisections with mid = (lo + hi) INV_ROOT(2 lo.hi); m = floor(t 2^K + 0.5). The grid index is an
// integer decision on the pixel's position: t is a `pix` (spanFraction), as a mobile shader takes
// it from highp gl_FragCoord; a float16 t (2^-11 relative) would move m by a grid step once 2^K
// nears 2^10. The halving itself is `real`.
real3 dichotomy(real3 A, real3 B, pix t, int K) {
    int n = 1 << K;
    int m = min(int(floor(t * pix(n) + 0.5)), n);
    if (m == 0) {
        return A;
    }
    if (m == n) {
        return B;
    }
    real3 lo = A;
    real3 hi = B;
    for (int l = 0; l < K; ++l) {
        real3 mid = (lo + hi) * INV_ROOT(R(2.0) * dot(lo, hi));
        if (((m >> (K - 1 - l)) & 1) != 0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}
#endif

// The digital segment of 2^k pixels holding the pixel (docs/formulas.md#digital-segments): its end
// positions xl, xp (pixel centres; the first starts at the first covered pixel centre) and the
// pixel's index v in it.
void segmentAt(Span sp, pix px, int k, out pix xl, out pix xp, out int v) {
    pix p0 = ceil(sp.xA - 0.5) + 0.5;
    int j = max(int(floor(px - p0)), 0);
    xl = p0 + pix((j >> k) << k);
    xp = xl + pix(1 << k);
    v = j & ((1 << k) - 1);
}

#ifdef METHOD_COSINE
// The lighting model of glsl/shading.glsl from the cosines alone, for methods that approximate
// N.L and N.H rather than N (Bishop-Weimer, Hast-Euler): methodCosine(v) is the method's N.v.
// Twin: Lighting::shade_cosines in src/method/formulas.rs.
real methodCosine(real3 v);
real3 shadeCosines() {
    real3 c = R3(params.ambient.rgb);
    for (int i = 0; i < LIGHT_COUNT; ++i) {
        real d = max(methodCosine(R3(params.lightDir[i].xyz)), R(0.0));
        real s = max(methodCosine(R3(params.halfVec[i].xyz)), R(0.0));
        real sp = HAS_SPECULAR && s > R(0.0) ? pow(s, R(params.specular.w)) : R(0.0);
        c += R3(params.lightColor[i].rgb) * (R3(params.diffuse.rgb) * d + R3(params.specular.rgb) * sp);
    }
    return c;
}
#endif
