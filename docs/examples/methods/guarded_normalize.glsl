// A guarded normalize, as engines write it: N rsqrt(max(N.N, tiny)), never 0/0 (a zero normal
// comes out zero, not NaN). tiny is 1e-30 in float32 and float16's smallest normal number,
// 2^-14, in float16 (1e-30 is 0 there), chosen by BY_PRECISION (glsl/common.glsl rule 7).
// An example of `--method-file` (docs/your-method.md).
// shadelab-inputs: interpolated_normal
real3 methodNormal() {
    real3 n = R3(vNormal);
    real tiny = BY_PRECISION(R(1e-30), R(6.103515625e-05));
    return n * inversesqrt(max(dot(n, n), tiny));
}
