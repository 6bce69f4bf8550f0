// segments_k3 (docs/formulas.md#digital-segments): digital segments of 8 pixels, colour
// interpolated inside.
#define SEGMENT_K 3
#include "segments.glsl"
