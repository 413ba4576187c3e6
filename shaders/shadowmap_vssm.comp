#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_EXT_control_flow_attributes : require
// VSSM with the moments in float, for devices without shaderFloat64 (shadowmap_vssm.glsl).
#include "shadowmap_vssm.glsl"
