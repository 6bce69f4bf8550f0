// segments_k3 (FORMULAS.md 2.16): digital segments of 8 pixels, colour interpolated inside.
#define SEGMENT_K 3
#include "segments.glsl"
