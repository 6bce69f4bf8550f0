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
