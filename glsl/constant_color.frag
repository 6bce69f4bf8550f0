#version 450
// The cost floor for a pass without a normal target (the timed draws): the colour alone.
#define STAGE_FRAGMENT
#define COLOR_ONLY
#include "common.glsl"
#include "constant_main.glsl"
