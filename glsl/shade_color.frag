#version 450
// A method's fragment program for a pass without a normal target (the timed draws of bench,
// the programs `shadelab isa` compiles): the colour alone, so that the program writes no output
// the pass has no attachment for.
#define STAGE_FRAGMENT
#define COLOR_ONLY
#include "common.glsl"
#include "shading.glsl"
#include "shade_main.glsl"
