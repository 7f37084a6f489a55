#include "methods/common/caustic_reach.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/parallel.h"
#include "core/photon_tracer.h"

namespace causticbench {

double CausticReach::radius_holding(double fraction) const {
  if (hits.empty() || !(total_flux > 0.0)) return 0.0;
  const double wanted = fraction * total_flux;
  double sum = 0.0;
  for (const Hit& hit : hits) {
    sum += hit.flux;
    if (sum >= wanted) return hit.distance;
  }
  return hits.back().distance;
}

double CausticReach::fraction_beyond(double radius) const {
  if (hits.empty() || !(total_flux > 0.0)) return 0.0;
  double beyond = 0.0;
  for (const Hit& hit : hits)
    if (hit.distance > radius) beyond += hit.flux;
  return beyond / total_flux;
}

double CausticReach::paper_flux_within(double radius) const {
  double flux = 0.0;
  for (const Hit& hit : hits)
    if (hit.distance <= radius) flux += hit.flux * hit.paper_share;
  return flux;
}

double paper_orientation_share(const Vec3& travel, const Vec3& normal, const Vec3& from_center) {
  const double distance = glm::length(from_center);
  if (!(distance > 0.0)) return 0.0;  // the lookup's cosine at the centre itself
  const Vec3 direction = from_center / static_cast<float>(distance);
  const double stored = std::max(0.0f, glm::dot(travel, direction));
  const double receiver = std::max(0.0f, -glm::dot(normal, direction));
  return stored * receiver / std::max(kGrazingCosine, static_cast<double>(std::fabs(glm::dot(normal, travel))));
}

CausticReach probe_caustic_reach(const SceneFrame& frame, const Tracer& tracer, int object, const BuildSpaceMap& map,
                                 const BoundingSphere& build_bounds, uint64_t photons, uint64_t seed) {
  CausticReach reach;
  reach.photons = photons;
  const CausticPhotonTracer photon_tracer(tracer, PhotonTracerSettings{seed}, frame.lights, {object});
  if (!photon_tracer.has_targets() || !(build_bounds.radius > 0.0f)) return reach;
  // One slot per photon index, filled in parallel: the hits do not depend on the thread count.
  std::vector<std::optional<CausticReach::Hit>> slots(photons);
  parallel_blocks(photons, 1024, [&](size_t begin, size_t end, size_t) {
    std::vector<Photon> deposits;
    PhotonStats stats;
    for (size_t i = begin; i < end; ++i) {
      deposits.clear();
      photon_tracer.trace_one(i, deposits, stats);
      if (deposits.empty()) continue;
      // The first deposit of a path is its first receiver: where the object's light first lands.
      const Photon& first = deposits.front();
      const double flux = static_cast<double>(luminance(first.power));
      if (!(flux > 0.0)) continue;
      const Vec3 from_center = map.point(first.position) - build_bounds.center;
      const Vec3 travel = glm::normalize(map.vector(first.direction));
      const Vec3 normal = glm::normalize(map.normals * first.normal);
      slots[i] = CausticReach::Hit{glm::length(from_center) / build_bounds.radius, flux,
                                   paper_orientation_share(travel, normal, from_center)};
    }
  });
  for (const std::optional<CausticReach::Hit>& slot : slots) {
    if (!slot) continue;
    reach.hits.push_back(*slot);
    reach.total_flux += slot->flux;
  }
  std::sort(reach.hits.begin(), reach.hits.end(),
            [](const CausticReach::Hit& a, const CausticReach::Hit& b) { return a.distance < b.distance; });
  return reach;
}

}  // namespace causticbench
