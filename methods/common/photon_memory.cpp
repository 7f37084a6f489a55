#include "methods/common/photon_memory.h"

#include <algorithm>
#include <vector>

#include "core/photon_tracer.h"

namespace causticbench {

double deposits_per_photon_bound(const PrepareContext& context, uint64_t seed, int max_bounces) {
  bool several_per_path = false;
  for (const SceneObject& object : context.scene.objects)
    several_per_path = several_per_path || object.material.kind == MaterialKind::diffuse_mirror;
  if (!several_per_path) return 1.0;
  constexpr uint64_t kPilot = 16384;
  const CausticPhotonTracer tracer(context.tracer, PhotonTracerSettings{seed, max_bounces});
  std::vector<Photon> photons;
  PhotonStats stats;
  tracer.trace(0, kPilot, photons, stats);
  return std::max(1.0, 1.25 * static_cast<double>(photons.size()) / static_cast<double>(kPilot));
}

}  // namespace causticbench
