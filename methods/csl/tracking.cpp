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

double axis_distance(const BundleAxis& first, double first_convergence, const BundleAxis& second,
                     double second_convergence, const BoundingSphere& bounds) {
  const glm::dvec3 centre(bounds.center);
  const glm::dvec3 b0 = nearest_on_axis(first, centre), b1 = nearest_on_axis(second, centre);
  const double diameter = 2.0 * bounds.radius;
  const glm::dvec3 turned = first.direction - second.direction;
  const double converged = first_convergence - second_convergence;
  return std::sqrt(glm::dot(b0 - b1, b0 - b1) + diameter * diameter * (glm::dot(turned, turned) + converged * converged));
}

double convergence_angle(const SpotLight& light) {
  if (light.image.size() == 0) return 0.0;
  const int channels = light.image.channels();
  auto flux_within = [&](double r) {
    double flux[3] = {0.0, 0.0, 0.0}, sum = 0.0;
    light.image.flux_within(r, flux);
    for (int c = 0; c < channels; ++c) sum += flux[c];
    return sum;
  };
  const double total = flux_within(light.image.max_radius());
  if (!(total > 0.0)) return 0.0;
  double low = 0.0, high = light.image.max_radius();
  for (int step = 0; step < 50; ++step) {
    const double middle = 0.5 * (low + high);
    (flux_within(middle) < 0.5 * total ? low : high) = middle;
  }
  const double r = 0.5 * (low + high);
  return std::atan(r * light.profile.g(r));
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
  const glm::dvec3 centre(bounds.center);
  for (int step = 1; step <= settings.steps; ++step) {
    const Vec3 direction = step == settings.steps ? to_light : slerp(set.direction, to_light, double(step) / settings.steps);
    const ObjectRays rays = trace_object_rays(tracer, bounds, direction, settings.rays_per_side, settings.tree);
    // Every axis refines on every ray. Taking each bundle's rays out before the next refined (as
    // extraction does) paired the slices of one converging field that extraction cuts on a mesh, and
    // the interpolated frames flickered more for it (see the README, "Tracking order").
    const std::vector<uint8_t> active(rays.rays.size(), 1);
    for (size_t i = 0; i < axes.size(); ++i) {
      const Bundle bundle = refine_bundle(rays.rays, active, axes[i], settings.bundle);
      if (bundle.members.empty()) {
        // No ray near the axis any more: it stays where it was (and is likely left unmatched).
        if (!stuck[i]) ++lost;
        stuck[i] = 1;
        continue;
      }
      // The new axis, with the light plane's origin as far along it from the point nearest the
      // object's centre as it was along the old one.
      const double along = glm::dot(axes[i].origin - centre, axes[i].direction);
      BundleAxis moved;
      moved.direction = bundle.axis.direction;
      moved.origin = nearest_on_axis(bundle.axis, centre) + along * moved.direction;
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
  std::vector<double> first_convergence, second_convergence;
  for (const SpotLight& light : first.lights) first_convergence.push_back(convergence_angle(light));
  for (const SpotLight& light : second.lights) second_convergence.push_back(convergence_angle(light));
  std::vector<std::tuple<double, int, int>> candidates;
  for (size_t i = 0; i < moved.size(); ++i) {
    for (size_t j = 0; j < second.lights.size(); ++j) {
      const double distance =
          axis_distance(moved[i], first_convergence[i], axis_of(second.lights[j]), second_convergence[j], bounds);
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
