#version 450
// A splat's weight at this texel's centre: the Gaussian of splat.cpp (sigma half the radius, cut at it)
// over the sum of the photon's weights, times its flux; blending adds it to the caustic map.
layout(location = 0) flat in vec4 centre_radius_total;
layout(location = 1) flat in vec3 flux;
layout(location = 0) out vec4 added;

void main() {
  const float radius = centre_radius_total.z;
  if (radius <= 0.0) {
    added = vec4(flux, 0.0);
    return;
  }
  const vec2 d = gl_FragCoord.xy - centre_radius_total.xy;
  const float d2 = dot(d, d);
  if (d2 > radius * radius) discard;
  const float sigma = 0.5 * radius;
  added = vec4(flux * (exp(-d2 / (2.0 * sigma * sigma)) / centre_radius_total.w), 0.0);
}
