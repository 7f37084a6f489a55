// The evaluation of a caustic spot light at a receiver point (Liu et al. 2008, Sections 2.2 to 2.4),
// for any image the Image concept of spot_light.h describes; included by spot_light.h.
#pragma once

#include <glm/geometric.hpp>

namespace causticbench::csl {

template <class Image, class Visible>
int evaluate_spot_light(const SpotGeometry& light, const Image& image, const Vec3& point, const Vec3& normal,
                        float footprint_radius, const EvaluationSettings& settings, float* out, const Visible& visible) {
  const Profile& profile = light.profile;
  const int channels = image.channels();
  const glm::dvec3 offset = glm::dvec3(point) - glm::dvec3(light.origin);
  const glm::dvec3 a(light.axis);
  const double z = glm::dot(offset, a);
  if (!(z > 0.0)) return 0;  // the rays start at the light plane
  glm::dvec3 across = offset - z * a;
  double rho = glm::length(across);
  const double max_radius = image.max_radius();
  float value[3];
  if (settings.on_axis == OnAxis::epsilon && rho < settings.axis_epsilon) {
    // The paper's treatment: move the point out to epsilon from the axis.
    across = rho > 0.0 ? across * (settings.axis_epsilon / rho) : settings.axis_epsilon * glm::dvec3(light.u);
    rho = settings.axis_epsilon;
  } else if (settings.on_axis == OnAxis::integrate && rho < footprint_radius) {
    // The disk of the receiver's footprint, centred on the axis, gathers the flux of every ray whose
    // signed radius at this height is within it: the central rays and the ring focused here. Its
    // flux over its area is the limit the point values average to (finite where they diverge).
    const double disk = footprint_radius;
    const Radii edges = profile.radii(z, disk, max_radius);
    double breaks[5] = {0.0, max_radius, 0.0, 0.0, 0.0};
    int count = 2;
    for (int i = 0; i < edges.count; ++i) breaks[count++] = edges.radius[i];
    std::sort(breaks, breaks + count);
    double flux[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i + 1 < count; ++i) {
      const double middle = 0.5 * (breaks[i] + breaks[i + 1]);
      if (!(breaks[i + 1] > breaks[i]) || std::fabs(profile.s(middle, z)) >= disk) continue;
      double inner[3], outer[3];
      image.flux_within(breaks[i], inner);
      image.flux_within(breaks[i + 1], outer);
      for (int c = 0; c < channels; ++c) flux[c] += outer[c] - inner[c];
    }
    const double cosine = std::max(0.0, -glm::dot(glm::dvec3(normal), a));
    if (cosine > 0.0 && !visible(a, glm::dvec3(light.origin))) return 0;
    const double area = kPiDouble * disk * disk;
    for (int c = 0; c < channels; ++c) out[c] += static_cast<float>(flux[c] / area * cosine);
    return 1;
  }
  if (!(rho > 0.0)) return 0;
  const glm::dvec3 outward = across / rho;
  const Radii radii = profile.radii(z, rho, max_radius);
  int contributing = 0;
  for (int i = 0; i < radii.count; ++i) {
    const double r = radii.radius[i];
    const glm::dvec3 from = (radii.side[i] * r) * outward;  // p - c
    const double x = glm::dot(from, glm::dvec3(light.u)), y = glm::dot(from, glm::dvec3(light.v));
    if (!image.lookup(x, y, value)) continue;  // beyond the light plane's image
    // Eq. 4, bounded so that a point exactly on the envelope where two radii merge stays finite.
    const double correction = settings.intensity_correction ? 1.0 / std::max(1e-6, profile.area_ratio(r, z)) : 1.0;
    const glm::dvec3 direction = glm::normalize(a - profile.g(r) * from);
    // The image holds flux per unit light-plane area; a receiver facing n takes |n.e| / |a.e| of it.
    const double cosine = std::max(0.0, -glm::dot(glm::dvec3(normal), direction)) / glm::dot(a, direction);
    if (cosine <= 0.0 || !visible(direction, glm::dvec3(light.origin) + from)) continue;
    for (int c = 0; c < channels; ++c) out[c] += static_cast<float>(value[c] * correction * cosine);
    ++contributing;
  }
  return contributing;
}


}  // namespace causticbench::csl
