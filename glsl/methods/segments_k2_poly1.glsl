// segments_k2_poly1 (docs/formulas.md#digital-segments): digital segments of 4 pixels, inner
// normals by dichotomy with the degree-1 inverse root 0.64 - 0.07 z (docs/formulas.md#dichotomy).
#define SEGMENT_K 2
#define INV_ROOT(z) (R(0.64) - R(0.07) * (z))
#include "segments.glsl"
