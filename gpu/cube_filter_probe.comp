// One filtered cube-map lookup per query: direction and the two gradients of textureGrad.
// Used by gpu/cube_filter_check.cpp to test whether a device's sampler honours explicit gradients.
#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Queries { vec4 query[]; };  // direction, gradient x, gradient y
layout(std430, binding = 1) writeonly buffer Results { vec4 result[]; };
layout(binding = 2) uniform samplerCube map;
layout(push_constant) uniform Parameters { uint count; } p;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= p.count) return;
  result[i] = textureGrad(map, query[3u * i].xyz, query[3u * i + 1u].xyz, query[3u * i + 2u].xyz);
}
