#include "methods/common/light_view.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace causticbench {

namespace {

// The solid angle of the rectangle [0, u] x [0, v] of the plane at unit depth, seen from the eye
// (signed with u v): the primitive of du dv / (1 + u^2 + v^2)^(3/2).
double corner_solid_angle(double u, double v) { return std::atan(u * v / std::sqrt(1.0 + u * u + v * v)); }

}  // namespace

LightView LightView::orthographic(const Vec3& travel, const Vec3& centre, double half_extent) {
  LightView view;
  view.orthographic_ = true;
  view.axis_ = glm::normalize(travel);
  view.eye_ = centre;
  orthonormal_basis(view.axis_, view.right_, view.up_);
  view.half_extent_ = half_extent;
  return view;
}

LightView LightView::perspective(const Vec3& eye, const Vec3& centre, double tan_half) {
  LightView view;
  view.orthographic_ = false;
  view.eye_ = eye;
  view.axis_ = glm::normalize(centre - eye);
  orthonormal_basis(view.axis_, view.right_, view.up_);
  view.half_extent_ = tan_half;
  return view;
}

std::optional<LightView::Projected> LightView::project(const Vec3& point) const {
  const glm::dvec3 d = glm::dvec3(point) - glm::dvec3(eye_);
  double x = glm::dot(d, glm::dvec3(right_)), y = glm::dot(d, glm::dvec3(up_)), z = glm::dot(d, glm::dvec3(axis_));
  double depth = z;
  if (!orthographic_) {
    if (z <= 1e-9 * glm::length(d)) return std::nullopt;
    x /= z;
    y /= z;
    depth = glm::length(d);  // along the ray from the light, as the receiver map stores it
  }
  return Projected{(x - offset_s_) / (2.0 * half_extent_) + 0.5, (y - offset_t_) / (2.0 * half_extent_) + 0.5, depth};
}

Ray LightView::ray(double s, double t, double back) const {
  const double x = offset_s_ + (2.0 * s - 1.0) * half_extent_, y = offset_t_ + (2.0 * t - 1.0) * half_extent_;
  if (orthographic_) {
    const glm::dvec3 origin = glm::dvec3(eye_) + x * glm::dvec3(right_) + y * glm::dvec3(up_) - back * glm::dvec3(axis_);
    return Ray{Vec3(origin), axis_};
  }
  const glm::dvec3 direction = glm::dvec3(axis_) + x * glm::dvec3(right_) + y * glm::dvec3(up_);
  return Ray{eye_, Vec3(glm::normalize(direction))};
}

Vec3 LightView::travel_at(const Vec3& point) const {
  return orthographic_ ? axis_ : glm::normalize(point - eye_);
}

double LightView::texel_measure(int x, int y, int n) const {
  const double side = 2.0 * half_extent_ / n;
  if (orthographic_) return side * side;
  const double u0 = offset_s_ - half_extent_ + x * side, v0 = offset_t_ - half_extent_ + y * side;
  const double u1 = u0 + side, v1 = v0 + side;
  return corner_solid_angle(u1, v1) - corner_solid_angle(u0, v1) - corner_solid_angle(u1, v0) + corner_solid_angle(u0, v0);
}

std::optional<LightView> LightView::fitted(const LightView& like, const std::vector<Vec3>& points, double margin,
                                          double widest_tan) {
  double low_x = std::numeric_limits<double>::infinity(), low_y = low_x, high_x = -low_x, high_y = -low_x;
  for (const Vec3& point : points) {
    const glm::dvec3 d = glm::dvec3(point) - glm::dvec3(like.eye_);
    double x = glm::dot(d, glm::dvec3(like.right_)), y = glm::dot(d, glm::dvec3(like.up_));
    if (!like.orthographic_) {
      const double z = glm::dot(d, glm::dvec3(like.axis_));
      if (z <= 1e-6 * glm::length(d)) continue;  // behind the eye: no window of this view holds it
      x = std::clamp(x / z, -widest_tan, widest_tan);
      y = std::clamp(y / z, -widest_tan, widest_tan);
    }
    low_x = std::min(low_x, x), high_x = std::max(high_x, x);
    low_y = std::min(low_y, y), high_y = std::max(high_y, y);
  }
  if (!std::isfinite(low_x)) return std::nullopt;
  LightView view = like;
  view.offset_s_ = 0.5 * (low_x + high_x);
  view.offset_t_ = 0.5 * (low_y + high_y);
  view.half_extent_ = std::max({0.5 * (high_x - low_x), 0.5 * (high_y - low_y), 1e-6}) * (1.0 + margin);
  if (!like.orthographic_) view.half_extent_ = std::min(view.half_extent_, widest_tan);
  return view;
}

std::optional<LightView> light_view_of(const LightFrame& light, const BoundingSphere& bounds, double max_half_angle) {
  if (light.kind == LightKind::directional)
    return LightView::orthographic(-light.direction_to_light, bounds.center, bounds.radius);
  if (light.kind != LightKind::point) return std::nullopt;
  const double distance = glm::length(glm::dvec3(bounds.center) - glm::dvec3(light.position));
  const double widest = std::tan(max_half_angle);
  // The tangent of the silhouette cone's half-angle: r / sqrt(d^2 - r^2).
  const double silhouette = distance > bounds.radius * 1.0001
                                ? bounds.radius / std::sqrt(distance * distance - double(bounds.radius) * bounds.radius)
                                : widest;
  Vec3 centre = bounds.center;
  if (distance < 1e-6) centre = light.position + Vec3(0, -1, 0);  // a light at the centre: look down
  return LightView::perspective(light.position, centre, std::min(silhouette, widest));
}

}  // namespace causticbench
