// The receiver map, and where a photon's outgoing ray meets the receivers: the paper's image-space search
// over the map, or an exact ray.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.h"
#include "methods/caustic_mapping/pass_parts.h"

namespace causticbench::caustic_mapping {

long ReceiverMap::texel(double s, double t) const {
  if (!(s >= 0.0 && s < 1.0 && t >= 0.0 && t < 1.0)) return -1;
  const long x = std::min(resolution - 1, static_cast<int>(s * resolution));
  const long y = std::min(resolution - 1, static_cast<int>(t * resolution));
  return y * resolution + x;
}

double ReceiverMap::texel_side(double depth) const {
  const double side = 2.0 * view.half_extent() / resolution;
  return view.is_orthographic() ? side : side * depth;
}

bool ReceiverMap::sees(const LightView::Projected& at, long texel, const Vec3& point, const Vec3& normal) const {
  if (texel < 0 || !std::isfinite(depth[static_cast<size_t>(texel)])) return false;
  const double cosine = std::abs(glm::dot(normal, view.travel_at(point)));
  const double slope = std::min(20.0, std::sqrt(std::max(0.0, 1.0 - cosine * cosine)) / std::max(cosine, 1e-3));
  return std::abs(at.depth - depth[static_cast<size_t>(texel)]) <= texel_side(at.depth) * (1.5 + 2.0 * slope);
}

ReceiverMap render_receiver_map(const Tracer& tracer, const LightView& view, int resolution, double back, int object) {
  ReceiverMap map;
  map.view = view;
  map.object = object;
  map.resolution = resolution;
  const size_t texels = static_cast<size_t>(resolution) * resolution;
  map.position.assign(texels, Vec3(0.0f));
  map.normal.assign(texels, Vec3(0.0f));
  map.depth.assign(texels, std::numeric_limits<float>::infinity());
  parallel_blocks(texels, 1024, [&](size_t begin, size_t end, size_t) {
    for (size_t texel = begin; texel < end; ++texel) {
      const int x = static_cast<int>(texel % resolution), y = static_cast<int>(texel / resolution);
      SurfaceHit hit;
      if (!first_receiver(tracer, view.ray((x + 0.5) / resolution, (y + 0.5) / resolution, back), hit, object)) continue;
      const std::optional<LightView::Projected> projected = view.project(hit.position);
      if (!projected) continue;
      map.position[texel] = hit.position;
      map.normal[texel] = hit.shading_normal;
      map.depth[texel] = static_cast<float>(projected->depth);
    }
  });
  return map;
}

namespace {

// The texel of the receiver the map holds where `point` projects, or -1 (outside the window, or no receiver).
long receiver_at(const ReceiverMap& map, const Vec3& point, SearchFailure& failure) {
  const std::optional<LightView::Projected> projected = map.view.project(point);
  const long texel = projected ? map.texel(projected->s, projected->t) : -1;
  if (texel < 0) {
    failure = SearchFailure::left_view;
    return -1;
  }
  if (!std::isfinite(map.depth[static_cast<size_t>(texel)])) {
    failure = SearchFailure::no_receiver;
    return -1;
  }
  return texel;
}

}  // namespace

SearchResult search_receiver(const ReceiverMap& map, const Tracer& tracer, const Vec3& origin, const Vec3& direction,
                             int iterations, bool exact, bool refine) {
  SearchResult result;
  if (exact) {
    SurfaceHit hit;
    if (!first_receiver(tracer, Ray{origin + direction * tracer.epsilon(), direction}, hit, map.object)) {
      result.failure = SearchFailure::no_receiver;
      return result;
    }
    result.hit = hit.position;
    return result;
  }
  // The start (the paper's): the receiver the light sees behind the photon's own texel.
  long texel = receiver_at(map, origin, result.failure);
  ++result.steps;
  if (texel < 0) return result;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    const float distance = glm::length(map.position[static_cast<size_t>(texel)] - origin);
    texel = receiver_at(map, origin + direction * distance, result.failure);
    ++result.steps;
    if (texel < 0) return result;
  }
  // Converged when the receiver found lies on the ray, to within what one texel of the map spans on that
  // receiver (its side, stretched by the receiver's slope to the light): otherwise the light's view of
  // the receivers is not what the ray meets (a fold, an overhang, a wall the light cannot see), and the
  // photon is dropped and counted rather than misplaced.
  const Vec3 receiver = map.position[static_cast<size_t>(texel)];
  const Vec3 offset = receiver - origin;
  const float along = glm::dot(offset, direction);
  const float off_ray = glm::length(offset - direction * along);
  const double facing = std::max(0.05f, std::abs(glm::dot(map.normal[static_cast<size_t>(texel)],
                                                          map.view.travel_at(receiver))));
  const double tolerance = map.texel_side(map.depth[static_cast<size_t>(texel)]) * (1.0 + 1.0 / facing);
  if (along <= 0.0f || off_ray > tolerance) {
    result.failure = SearchFailure::not_converged;
    return result;
  }
  result.hit = receiver;
  // The paper takes the texel's receiver as the hit, which snaps every photon to the map's grid (on a
  // flat mirror's beam: rows 15 % apart, 9 % of the flux moved out of the interior). Refined, the ray
  // meets the plane of that receiver instead: exact on a locally flat receiver, one dot product more.
  if (refine) {
    const Vec3 normal = map.normal[static_cast<size_t>(texel)];
    const float facing_ray = glm::dot(direction, normal);
    if (std::abs(facing_ray) > 1e-3f) {
      const float distance = glm::dot(receiver - origin, normal) / facing_ray;
      if (distance > 0.0f) result.hit = origin + direction * distance;
    }
  }
  return result;
}

}  // namespace causticbench::caustic_mapping
