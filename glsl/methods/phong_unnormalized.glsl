// phong_unnormalized: the interpolated normal used as it is; the cost floor of every
// normalization method and its error ceiling.
vec3 methodNormal() {
    return vNormal;
}
