// phong_unnormalized: the interpolated normal used as it is; the cost floor of every
// normalization method and its error ceiling.
real3 methodNormal() {
    return R3(vNormal);
}
