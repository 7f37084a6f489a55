#include "methods/csl/interpolation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace causticbench::csl {

void BlendedImage::add(const Source& source) {
  if (count_ == 3) throw std::logic_error("BlendedImage: more than three sources");
  sources_[count_++] = source;
  channels_ = std::max(channels_, source.image->channels());
  max_radius_ = std::max(max_radius_, source.image->max_radius());
  if (source.image->support_radius() > 0.0) {
    support_radius_ = std::max(support_radius_, source.image->support_radius() * (1.0 + 1e-5));
  }
}

bool BlendedImage::lookup(double x, double y, float* out) const {
  for (int c = 0; c < channels_; ++c) out[c] = 0.0f;
  bool inside = false;
  float value[3];
  for (int i = 0; i < count_; ++i) {
    const Source& source = sources_[i];
    const double sx = source.map[0] * x + source.map[1] * y, sy = source.map[2] * x + source.map[3] * y;
    const double half = source.image->half_size();
    if (std::fabs(sx) > half || std::fabs(sy) > half) continue;
    inside = true;
    source.image->lookup(static_cast<float>(sx), static_cast<float>(sy), value);
    if (source.image->channels() == channels_) {
      for (int c = 0; c < channels_; ++c) out[c] += source.weight * value[c];
    } else {  // a one-channel image under a coloured blend: the same value in every channel
      for (int c = 0; c < channels_; ++c) out[c] += source.weight * value[0];
    }
  }
  return inside;
}

void BlendedImage::flux_within(double r, double* out) const {
  // The flux within a radius does not change when a plane turns about its axis.
  for (int c = 0; c < channels_; ++c) out[c] = 0.0;
  double flux[3];
  for (int i = 0; i < count_; ++i) {
    const Source& source = sources_[i];
    source.image->flux_within(r, flux);
    for (int c = 0; c < channels_; ++c) out[c] += source.weight * flux[source.image->channels() == channels_ ? c : 0];
  }
}

glm::dvec3 spherical_mean(const std::array<glm::dvec3, 3>& directions, const std::array<double, 3>& weights) {
  int positive = 0, only = 0;
  glm::dvec3 sum(0.0);
  for (int i = 0; i < 3; ++i) {
    if (weights[i] > 0.0) {
      ++positive;
      only = i;
      sum += weights[i] * directions[i];
    }
  }
  if (positive == 1) return directions[only];
  if (!(glm::length(sum) > 1e-12)) return positive > 0 ? directions[only] : glm::dvec3(0.0, 0.0, 1.0);
  glm::dvec3 q = glm::normalize(sum);
  // Newton-like fixed point of Buss & Fillmore: move q along the weighted mean of the log maps.
  for (int iteration = 0; iteration < 32; ++iteration) {
    glm::dvec3 step(0.0);
    for (int i = 0; i < 3; ++i) {
      if (!(weights[i] > 0.0)) continue;
      const double cosine = std::clamp(glm::dot(q, directions[i]), -1.0, 1.0);
      const double angle = std::acos(cosine);
      const glm::dvec3 tangent = directions[i] - cosine * q;
      const double length = glm::length(tangent);
      if (length > 1e-15) step += weights[i] * angle / length * tangent;
    }
    const double size = glm::length(step);
    if (size < 1e-14) break;
    q = glm::normalize(std::cos(size) * q + std::sin(size) / size * step);
  }
  return q;
}

namespace {

// The rotation taking unit p to unit q about p x q (Rodrigues), applied to x.
glm::dvec3 rotate_onto(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& x) {
  const glm::dvec3 k = glm::cross(p, q);
  const double c = glm::dot(p, q);
  if (1.0 + c < 1e-12) return -x;  // opposite axes: no unique rotation; a half turn's image of the plane
  return x * c + glm::cross(k, x) + k * (glm::dot(k, x) / (1.0 + c));
}

}  // namespace

void plane_map(const SpotGeometry& to, const SpotGeometry& from, double* map) {
  if (to.axis == from.axis && to.u == from.u && to.v == from.v) {
    map[0] = 1.0, map[1] = 0.0, map[2] = 0.0, map[3] = 1.0;
    return;
  }
  // A point x u + y v of `to`'s plane, turned back onto `from`'s plane.
  const glm::dvec3 a(to.axis), a_from(from.axis);
  const glm::dvec3 u = rotate_onto(a, a_from, glm::dvec3(to.u)), v = rotate_onto(a, a_from, glm::dvec3(to.v));
  map[0] = glm::dot(u, glm::dvec3(from.u));
  map[1] = glm::dot(v, glm::dvec3(from.u));
  map[2] = glm::dot(u, glm::dvec3(from.v));
  map[3] = glm::dot(v, glm::dvec3(from.v));
}

std::optional<InterpolatedSpotLight> interpolate_triple(const std::array<TripleCorner, 3>& corners,
                                                        FocusInterpolation focus) {
  double present = 0.0;
  bool lit = false;
  for (const TripleCorner& corner : corners) {
    if (corner.light == nullptr) continue;
    present += corner.weight;
    lit = lit || (corner.adds && corner.weight > 0.0f);
  }
  if (!lit || !(present > 0.0)) return std::nullopt;
  // The geometry from the corners that have a light, their weights renormalised.
  std::array<double, 3> weights{0.0, 0.0, 0.0};
  std::array<glm::dvec3, 3> axes{};
  int contributors = 0, only = 0;
  for (int i = 0; i < 3; ++i) {
    if (corners[i].light == nullptr || !(corners[i].weight > 0.0f)) continue;
    weights[i] = corners[i].weight / present;
    axes[i] = glm::dvec3(corners[i].light->axis);
    ++contributors;
    only = i;
  }
  InterpolatedSpotLight result;
  if (contributors == 1) {
    // One corner: its geometry exactly, not a rounding of it.
    result.geometry = *corners[only].light;
  } else {
    glm::dvec3 origin(0.0);
    double kappa = 0.0, alpha = 0.0, beta = 0.0;
    bool focusing = true;
    for (int i = 0; i < 3; ++i) {
      if (!(weights[i] > 0.0)) continue;
      const SpotLight& light = *corners[i].light;
      origin += weights[i] * glm::dvec3(light.origin);
      kappa += weights[i] * light.profile.kappa;
      beta += weights[i] * light.profile.beta;
      focusing = focusing && light.profile.kappa > 0.0;
      if (light.profile.kappa > 0.0) alpha += weights[i] / light.profile.kappa;
    }
    result.geometry.axis = Vec3(spherical_mean(axes, weights));
    result.geometry.origin = Vec3(origin);
    result.geometry.profile.kappa = focus == FocusInterpolation::distance && focusing ? 1.0 / alpha : kappa;
    result.geometry.profile.beta = beta;
    set_plane_axes(result.geometry);
  }
  for (const TripleCorner& corner : corners) {
    if (corner.light == nullptr || !corner.adds || !(corner.weight > 0.0f) || corner.light->image.size() == 0) continue;
    BlendedImage::Source source;
    source.image = &corner.light->image;
    source.weight = corner.weight;
    plane_map(result.geometry, *corner.light, source.map);
    result.image.add(source);
  }
  if (result.image.count() == 0) return std::nullopt;
  return result;
}

}  // namespace causticbench::csl
