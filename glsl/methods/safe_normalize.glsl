// safe_normalize (issue 23): Unity's SafeNormalize (Core RP Library, ShaderLibrary/Common.hlsl:
// inVec * rsqrt(max(REAL_MIN, dot(inVec, inVec))), REAL_MIN = HALF_MIN = 2^-14 in half,
// Macros.hlsl). Exact normalisation wherever N.N >= 2^-14; a shorter N (whose float16 N.N is
// subnormal or 0) comes out shorter than unit instead of 0/0.
real3 methodNormal() {
    real3 n = R3(vNormal);
    real z = dot(n, n);
    return n * inversesqrt(max(z, R(6.103515625e-05)));
}
