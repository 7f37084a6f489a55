#version 450
// The light-view passes' vertex stage (shadow mapping's): every scene vertex (two vec4: position and
// object; normal and d_N) projected into a pass's light view (common.glsl's View), with reversed depth
// (1 nearest, 0 at the far end of the view's range) so that the depth test keeps the nearest surface.
// A vertex of an object the pass does not draw is sent outside the clip volume, its triangle with it.
layout(std430, binding = 0) readonly buffer Vertices { vec4 vertices[]; };
layout(std430, binding = 1) readonly buffer Objects { vec4 objects[]; };
layout(std430, binding = 2) readonly buffer Views { vec4 views[]; };

layout(push_constant) uniform Parameters {
  uint view;    // index into views
  uint mode;    // 0 receivers (the objects that receive caustics, but `object`), 1 every object, 2 `object` only
  uint object;
} parameters;

#define NO_RECEIVER_MAP
#include "common.glsl"

layout(location = 0) out vec3 position;
layout(location = 1) out vec3 normal;
layout(location = 2) out float normal_depth;
layout(location = 3) flat out float object;
layout(location = 4) flat out vec3 face_normal;  // the triangle's, on the side its vertex normals face

const uint kObjectVec4 = 5u;

bool drawn(uint index) {
  if (parameters.mode == 1u) return true;
  if (parameters.mode == 2u) return index == parameters.object;
  return index != parameters.object && objects[kObjectVec4 * index].y != 0.0;
}

void main() {
  const uint vertex = uint(gl_VertexIndex);
  const vec4 at = vertices[2u * vertex];
  position = at.xyz;
  normal = vertices[2u * vertex + 1u].xyz;
  normal_depth = vertices[2u * vertex + 1u].w;
  object = at.w;
  const uint first = vertex - vertex % 3u;
  const vec3 p0 = vertices[2u * first].xyz, p1 = vertices[2u * first + 2u].xyz, p2 = vertices[2u * first + 4u].xyz;
  const vec3 normals = vertices[2u * first + 1u].xyz + vertices[2u * first + 3u].xyz + vertices[2u * first + 5u].xyz;
  face_normal = cross(p1 - p0, p2 - p0);
  if (dot(face_normal, normals) < 0.0) face_normal = -face_normal;
  if (!drawn(uint(at.w))) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  const View view = view_at(parameters.view);
  const vec3 d = at.xyz - view.eye;
  const float x = dot(d, view.right), y = dot(d, view.up), z = dot(d, view.axis);
  if (view.orthographic) {
    gl_Position = vec4((x - view.offset_s) / view.half_extent, (y - view.offset_t) / view.half_extent,
                       (view.far - z) / (view.far - view.near), 1.0);
  } else {
    // Clip w = z: the window's (x / z, y / z); depth near / z, 1 at the near plane, clipped before it.
    gl_Position = vec4((x - view.offset_s * z) / view.half_extent, (y - view.offset_t * z) / view.half_extent,
                       view.near, z);
  }
}
