// Two Newton-Raphson steps for 1/sqrt(z), z = N.N, from y0 = 1 (newton_raphson takes one):
// y1 = (3 - z)/2, y2 = y1 (3 - z y1^2)/2. An example of `--method-file` (docs/your-method.md).
// shadelab-inputs: interpolated_normal
real3 methodNormal() {
    real3 n = R3(vNormal);
    real z = dot(n, n);
    real y = R(0.5) * (R(3.0) - z);
    y = y * (R(1.5) - R(0.5) * z * y * y);
    return n * y;
}
