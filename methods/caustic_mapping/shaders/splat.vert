#version 450
// The splats: one quad (two triangles) per photon, instanced, moved to the photon's landing in the
// caustic map and sized by its radius (a photon not landed is drawn nowhere). A point splat covers its
// own texel's centre only.
layout(std430, binding = 0) readonly buffer Landings { vec4 landings[]; };
layout(std430, binding = 1) readonly buffer Arriving { vec4 arriving[]; };
layout(std430, binding = 2) readonly buffer Splats { vec4 splats[]; };

layout(push_constant) uniform Parameters {
  uint first_photon;
  uint resolution;
} parameters;

layout(location = 0) flat out vec4 centre_radius_total;  // x, y, radius, weights' sum
layout(location = 1) flat out vec3 flux;

void main() {
  const uint photon = parameters.first_photon + uint(gl_InstanceIndex);
  const vec4 landing = landings[photon];
  const vec4 splat = splats[photon];
  const float n = float(parameters.resolution);
  centre_radius_total = vec4(landing.xy, splat.xy);
  flux = arriving[photon].xyz;
  if (landing.z != 0.0) {
    gl_Position = vec4(-2.0, -2.0, 0.0, 1.0);
    return;
  }
  const int corner = int[6](0, 1, 2, 2, 1, 3)[gl_VertexIndex];
  const vec2 side = vec2(corner & 1, corner >> 1);
  vec2 low, high;
  if (splat.x <= 0.0) {
    const vec2 texel = clamp(floor(landing.xy), vec2(0.0), vec2(n - 1.0));
    low = texel + 0.25;
    high = texel + 0.75;
  } else {
    // Half a texel beyond the radius, so that a texel centre exactly on it is drawn; the fragment stage cuts at it.
    low = landing.xy - splat.x - 0.5;
    high = landing.xy + splat.x + 0.5;
  }
  gl_Position = vec4(mix(low, high, side) / n * 2.0 - 1.0, 0.0, 1.0);
}
