#version 450
// The light-view passes' fragment stage, the nearest surface per texel (the depth test's) written as
// two RGBA32F targets. Mode 0, the receiver map: position and its depth from the light (LightView::
// project's); normal. Mode 1, the photon buffer's front: position and object; normal and d_N (Wyman's
// distance through the object along the inward normal, interpolated from the vertices). Mode 2, its
// back: the faces turned away from the light only, position and 1; normal.
layout(std430, binding = 0) readonly buffer Vertices { vec4 vertices[]; };
layout(std430, binding = 1) readonly buffer Objects { vec4 objects[]; };
layout(std430, binding = 2) readonly buffer Views { vec4 views[]; };

layout(push_constant) uniform Parameters {
  uint view;
  uint mode;
  uint object;
} parameters;

#define NO_RECEIVER_MAP
#include "common.glsl"

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in float normal_depth;
layout(location = 3) flat in float object;
layout(location = 4) flat in vec3 face_normal;

layout(location = 0) out vec4 first;
layout(location = 1) out vec4 second;

void main() {
  const View view = view_at(parameters.view);
  const vec3 unit = normalize(normal);
  if (parameters.mode == 0u) {
    vec3 projected;
    if (!project(view, position, projected)) discard;
    first = vec4(position, projected.z);
    second = vec4(unit, 0.0);
  } else if (parameters.mode == 1u) {
    first = vec4(position, object);
    second = vec4(unit, normal_depth);
  } else {
    if (dot(face_normal, travel_at(view, position)) <= 0.0) discard;  // faces the light: a front face
    first = vec4(position, 1.0);
    second = vec4(unit, 0.0);
  }
}
