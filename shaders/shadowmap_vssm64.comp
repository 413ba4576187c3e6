#version 450
#extension GL_GOOGLE_include_directive : require
// VSSM with the moments in double, where the device has shaderFloat64 (shadowmap_vssm.glsl).
#define VSSM_REAL double
#include "shadowmap_vssm.glsl"
