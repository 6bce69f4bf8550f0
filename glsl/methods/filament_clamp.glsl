// filament_clamp (issue 23): Filament's mediump clamp (shaders/src/common_math.glsl:
// MEDIUMP_FLT_MAX = 65504, saturateMediump(x) = min(x, MEDIUMP_FLT_MAX), applied in brdf.fs to
// values that overflow mediump) applied to N.N before normalising: exact below N.N = 65504;
// above it (|N| > 256, where a float16 N.N overflows to inf and N/|N| gives 0 or NaN) N comes
// out longer than unit but finite.
real3 methodNormal() {
    real3 n = R3(vNormal);
    real z = dot(n, n);
    return n * inversesqrt(min(z, R(65504.0)));
}
