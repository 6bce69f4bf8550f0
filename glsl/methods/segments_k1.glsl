// segments_k1 (docs/formulas.md#digital-segments): digital segments of 2 pixels, colour
// interpolated inside.
#define SEGMENT_K 1
#include "segments.glsl"
