// segments_k2 (FORMULAS.md 2.16): digital segments of 4 pixels, colour interpolated inside.
#define SEGMENT_K 2
#include "segments.glsl"
