#version 450
#extension GL_GOOGLE_include_directive : require
#include "foreground_io.h"
layout(local_size_x = FOREGROUND_LOCAL, local_size_y = FOREGROUND_LOCAL) in;
layout(binding = 0) uniform samplerBuffer beauty;
layout(binding = 1) uniform samplerBuffer depth;
layout(std430, binding = 2) writeonly buffer Fg { float fg[]; };
layout(push_constant) uniform Push { ForegroundPush pc; };

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  uint i = p.y * pc.width + p.x;
  uint n = pc.width * pc.height;
  bool bg = false;
  if (pc.has_alpha != 0u) bg = bg || texelFetch(beauty, int(3u * n + i)).r == 0.0;
  if (pc.has_depth != 0u) {
    float z = texelFetch(depth, int(i)).r;
    bg = bg || z <= 0.0 || z >= ISG_BACKGROUND_DEPTH;
  }
  fg[i] = bg ? 0.0 : 1.0;
}
