#version 450
// A method's fragment program for a pass with a normal target (compare, verify): the colour
// at location 0, the shading normal the method used at location 1.
#define STAGE_FRAGMENT
#include "common.glsl"
#include "shading.glsl"
#include "shade_main.glsl"
