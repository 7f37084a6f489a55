#include "methods/csl/tracking.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <tuple>

#include <glm/geometric.hpp>

#include "methods/csl/object_rays.h"

namespace causticbench::csl {

namespace {

// The unit direction a fraction t of the way along the great circle from `from` to `to`.
Vec3 slerp(const Vec3& from, const Vec3& to, double t) {
  const glm::dvec3 a(from), b(to);
  const double cosine = std::clamp(glm::dot(a, b), -1.0, 1.0);
  const double angle = std::acos(cosine);
  if (angle < 1e-12) return to;
  const double sine = std::sin(angle);
  return Vec3(glm::normalize(std::sin((1.0 - t) * angle) / sine * a + std::sin(t * angle) / sine * b));
}

glm::dvec3 nearest_on_axis(const BundleAxis& axis, const glm::dvec3& point) {
  return axis.origin + glm::dot(point - axis.origin, axis.direction) * axis.direction;
}

BundleAxis axis_of(const SpotLight& light) { return BundleAxis{glm::dvec3(light.origin), glm::dvec3(light.axis)}; }

}  // namespace

double axis_distance(const BundleAxis& first, const BundleAxis& second, const BoundingSphere& bounds) {
  const glm::dvec3 b0 = first.origin, b1 = second.origin;
  const double diameter = 2.0 * bounds.radius;
  const glm::dvec3 turned = first.direction - second.direction;
  return std::sqrt(glm::dot(b0 - b1, b0 - b1) + diameter * diameter * glm::dot(turned, turned));
}

SpotLight black_spot_light(const SpotLight& like, const BundleAxis& axis) {
  SpotLight black;
  black.origin = Vec3(axis.origin);
  black.axis = Vec3(glm::normalize(axis.direction));
  set_plane_axes(black);
  black.profile = like.profile;
  const int channels = like.image.size() > 0 ? like.image.channels() : 1;
  const float half = like.image.size() > 0 ? like.image.half_size() : 1.0f;
  black.image = IntensityImage(1, channels, half, std::vector<float>(channels, 0.0f), IntensityImage::Precision::float32);
  black.adds = false;
  return black;
}

std::vector<BundleAxis> track_axes(const Tracer& tracer, const BoundingSphere& bounds, const SpotLightSet& set,
                                   const Vec3& to_light, const TrackingSettings& settings, int& lost) {
  std::vector<BundleAxis> axes;
  for (const SpotLight& light : set.lights) axes.push_back(axis_of(light));
  std::vector<uint8_t> stuck(axes.size(), 0);
  lost = 0;
  if (axes.empty()) return axes;
  for (int step = 1; step <= settings.steps; ++step) {
    const Vec3 direction = step == settings.steps ? to_light : slerp(set.direction, to_light, double(step) / settings.steps);
    const ObjectRays rays = trace_object_rays(tracer, bounds, direction, settings.rays_per_side, settings.tree);
    const std::vector<uint8_t> active(rays.rays.size(), 1);
    for (size_t i = 0; i < axes.size(); ++i) {
      const Bundle bundle = refine_bundle(rays.rays, active, axes[i], settings.bundle);
      if (bundle.members.empty()) {
        // No ray near the axis any more: it stays where it was (and is likely left unmatched).
        if (!stuck[i]) ++lost;
        stuck[i] = 1;
        continue;
      }
      // The new axis, with the light plane's origin kept at the point of it nearest the old origin,
      // so that the plane moves continuously.
      BundleAxis moved;
      moved.direction = bundle.axis.direction;
      moved.origin = nearest_on_axis(bundle.axis, axes[i].origin);
      axes[i] = moved;
    }
  }
  return axes;
}

EdgeMatch match_neighbours(const Tracer& tracer, const BoundingSphere& bounds, const SpotLightSet& first,
                           const SpotLightSet& second, const TrackingSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  EdgeMatch match;
  const std::vector<BundleAxis> moved = track_axes(tracer, bounds, first, second.direction, settings, match.tracked_lost);
  // Every candidate pair within the threshold, nearest first (ties by index, so the order is fixed).
  std::vector<std::tuple<double, int, int>> candidates;
  for (size_t i = 0; i < moved.size(); ++i) {
    for (size_t j = 0; j < second.lights.size(); ++j) {
      const double distance = axis_distance(moved[i], axis_of(second.lights[j]), bounds);
      if (distance <= settings.match_distance) candidates.emplace_back(distance, static_cast<int>(i), static_cast<int>(j));
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<uint8_t> first_matched(first.lights.size(), 0), second_matched(second.lights.size(), 0);
  for (const auto& [distance, i, j] : candidates) {
    if (first_matched[i] || second_matched[j]) continue;
    first_matched[i] = second_matched[j] = 1;
    match.pairs.push_back(LightPair{i, j});
    match.distances.push_back(distance);
  }
  for (size_t i = 0; i < first.lights.size(); ++i) {
    if (first_matched[i]) continue;
    match.pairs.push_back(LightPair{static_cast<int32_t>(i), ~static_cast<int32_t>(match.black_second.size())});
    match.black_second.push_back(black_spot_light(first.lights[i], moved[i]));
  }
  for (size_t j = 0; j < second.lights.size(); ++j) {
    if (second_matched[j]) continue;
    match.pairs.push_back(LightPair{~static_cast<int32_t>(match.black_first.size()), static_cast<int32_t>(j)});
    match.black_first.push_back(black_spot_light(second.lights[j], axis_of(second.lights[j])));
  }
  match.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return match;
}

}  // namespace causticbench::csl
