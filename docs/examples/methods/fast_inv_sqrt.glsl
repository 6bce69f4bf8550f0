// The bit-trick inverse square root (Quake III; Lomont 2003): the float's bits as an integer,
// 0x5f3759df - (i >> 1) as a first guess of 1/sqrt(z), then one Newton step (max relative error
// 0.175 %). An example of `--method-file` (docs/your-method.md).
//
// The trick reads the bits of a float32, so it computes in float32 in both precisions (a float32
// detour in the float16 program: z, the guess and the Newton step are float32; the result is
// converted to `real` once). A float16 version would need its own magic constant on 16 bits.
// shadelab-inputs: interpolated_normal
real3 methodNormal() {
    vec3 n = vNormal;
    float z = dot(n, n);
    float y = intBitsToFloat(0x5f3759df - (floatBitsToInt(z) >> 1));
    y = y * (1.5 - 0.5 * z * y * y);
    return R3(n * y);
}
