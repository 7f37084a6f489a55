#version 450
// Each landed photon's splat (methods/caustic_mapping/splat.cpp): its radius in caustic-map texels (0: one
// texel), from the density cells for variable splats, and the sum of its Gaussian weights over the
// texels inside the map, by which the fragment stage divides so that every photon's flux lands whole.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Landings { vec4 landings[]; };
layout(std430, binding = 1) readonly buffer Counts { float counts[]; };
layout(std430, binding = 2) writeonly buffer Splats { vec4 splats[]; };

layout(push_constant) uniform Parameters {
  uint first_photon;
  uint photon_count;
  uint resolution;
  uint splat;  // 0 point, 1 gaussian, 2 variable
  float splat_radius;
  float splat_photons;
  float max_splat_radius;
} parameters;

const float kPi = 3.14159265358979;
const int kDensityCell = 4;

void main() {
  const uint index = gl_GlobalInvocationID.x;
  if (index >= parameters.photon_count) return;
  const uint photon = parameters.first_photon + index;
  const vec4 landing = landings[photon];
  if (landing.z != 0.0 || parameters.splat == 0u) {
    splats[photon] = vec4(0.0, 1.0, 0.0, 0.0);
    return;
  }
  const int n = int(parameters.resolution);
  float radius = parameters.splat_radius;
  if (parameters.splat == 2u) {
    const int cells = (n + kDensityCell - 1) / kDensityCell;
    const int cx = clamp(int(landing.x) / kDensityCell, 0, cells - 1), cy = clamp(int(landing.y) / kDensityCell, 0, cells - 1);
    const float density = counts[cy * cells + cx] / float(kDensityCell * kDensityCell);
    radius = clamp(sqrt(parameters.splat_photons / (kPi * density)), 0.5, parameters.max_splat_radius);
  }
  const float sigma = 0.5 * radius;
  const int x0 = max(0, int(floor(landing.x - radius))), x1 = min(n - 1, int(floor(landing.x + radius)));
  const int y0 = max(0, int(floor(landing.y - radius))), y1 = min(n - 1, int(floor(landing.y + radius)));
  float total = 0.0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const vec2 d = vec2(float(x) + 0.5, float(y) + 0.5) - landing.xy;
      const float d2 = dot(d, d);
      if (d2 <= radius * radius) total += exp(-d2 / (2.0 * sigma * sigma));
    }
  // A radius that reached no texel centre: the nearest texel, as a point splat.
  splats[photon] = total > 0.0 ? vec4(radius, total, 0.0, 0.0) : vec4(0.0, 1.0, 0.0, 0.0);
}
