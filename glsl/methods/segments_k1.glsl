// segments_k1 (FORMULAS.md 2.16): digital segments of 2 pixels, colour interpolated inside.
#define SEGMENT_K 1
#include "segments.glsl"
