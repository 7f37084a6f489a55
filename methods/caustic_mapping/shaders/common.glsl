// caustic_mapping's shaders: the light view and the receiver map, as methods/common/light_view.cpp and
// methods/caustic_mapping/receiver_search.cpp compute them (the CPU in double where it projects; here
// float). Record layouts: methods/caustic_mapping/frame_data.h. A pass has two views: its caustic map's
// (2 pass) and its photon buffer's (2 pass + 1).

struct View {
  vec3 eye;
  bool orthographic;
  vec3 axis;
  float half_extent;
  vec3 right;
  float offset_s;
  vec3 up;
  float offset_t;
  float near, far;  // the depth range a light-view pass rasterises
};

View view_at(uint index) {
  const uint at = 5u * index;
  View view;
  view.eye = views[at].xyz;
  view.orthographic = views[at].w != 0.0;
  view.axis = views[at + 1u].xyz;
  view.half_extent = views[at + 1u].w;
  view.right = views[at + 2u].xyz;
  view.offset_s = views[at + 2u].w;
  view.up = views[at + 3u].xyz;
  view.offset_t = views[at + 3u].w;
  view.near = views[at + 4u].x;
  view.far = views[at + 4u].y;
  return view;
}

// LightView::project: (s, t, depth), false behind a perspective eye.
bool project(View view, vec3 point, out vec3 projected) {
  const vec3 d = point - view.eye;
  float x = dot(d, view.right), y = dot(d, view.up);
  const float z = dot(d, view.axis);
  float depth = z;
  if (!view.orthographic) {
    if (z <= 1e-9 * length(d)) return false;
    x /= z;
    y /= z;
    depth = length(d);
  }
  projected = vec3((x - view.offset_s) / (2.0 * view.half_extent) + 0.5, (y - view.offset_t) / (2.0 * view.half_extent) + 0.5,
                   depth);
  return true;
}

vec3 travel_at(View view, vec3 point) { return view.orthographic ? view.axis : normalize(point - view.eye); }

// ReceiverMap::texel: the texel of window point (s, t) in an n x n map, or -1 outside the window.
int texel_of(vec3 projected, int n) {
  if (!(projected.x >= 0.0 && projected.x < 1.0 && projected.y >= 0.0 && projected.y < 1.0)) return -1;
  const int x = min(n - 1, int(projected.x * float(n)));
  const int y = min(n - 1, int(projected.y * float(n)));
  return y * n + x;
}

float texel_side(View view, int n, float depth) {
  const float side = 2.0 * view.half_extent / float(n);
  return view.orthographic ? side : side * depth;
}

#ifndef NO_RECEIVER_MAP  // a shader without the receivers binding
// The receiver map's texel `texel` of the n x n pass whose maps start at `first`: the pass's n^2
// positions (with their depth), then its n^2 normals, as the receiver pass renders them.
vec4 receiver_position(uint first, int texel) { return receivers[2u * first + uint(texel)]; }
vec3 receiver_normal(uint first, int n, int texel) { return receivers[2u * first + uint(n * n + texel)].xyz; }

// ReceiverMap::sees: the shadow-map test with its slope-scaled bias.
bool sees(View view, int n, uint first, vec3 projected, int texel, vec3 point, vec3 normal) {
  if (texel < 0) return false;
  const float depth = receiver_position(first, texel).w;
  if (isinf(depth)) return false;
  const float cosine = abs(dot(normal, travel_at(view, point)));
  const float slope = min(20.0, sqrt(max(0.0, 1.0 - cosine * cosine)) / max(cosine, 1e-3));
  return abs(projected.z - depth) <= texel_side(view, n, projected.z) * (1.5 + 2.0 * slope);
}
#endif
