#version 450
// The cost floor for a pass with a normal target.
#define STAGE_FRAGMENT
#include "common.glsl"
#include "constant_main.glsl"
