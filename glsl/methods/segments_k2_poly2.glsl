// segments_k2_poly2 (docs/formulas.md#digital-segments): digital segments of 4 pixels, inner
// normals by dichotomy with the degree-2 inverse root 0.014253 z^2 - 0.118922 z + 0.680850
// (docs/formulas.md#dichotomy).
#define SEGMENT_K 2
#define INV_ROOT(z) ((R(0.014253) * (z) - R(0.118922)) * (z) + R(0.680850))
#include "segments.glsl"
