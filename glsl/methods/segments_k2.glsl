// segments_k2 (docs/formulas.md#digital-segments): digital segments of 4 pixels, colour
// interpolated inside.
#define SEGMENT_K 2
#include "segments.glsl"
