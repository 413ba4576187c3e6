#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_EXT_control_flow_attributes : require
// VSSM with the moments in double, where the device has shaderFloat64 (shadowmap_vssm.glsl).
#define VSSM_REAL double
#include "shadowmap_vssm.glsl"
