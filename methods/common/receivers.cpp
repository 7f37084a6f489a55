#include "methods/common/receivers.h"

#include "core/scene.h"

namespace causticbench {

bool first_receiver(const Tracer& tracer, Ray ray, SurfaceHit& hit, int skip) {
  const Scene& scene = *tracer.frame().scene;
  // A ray can cross a specular object at most a few times (in and out of each); 64 covers any scene.
  for (int crossing = 0; crossing < 64; ++crossing) {
    if (!tracer.intersect(ray, hit)) return false;
    if (hit.object != skip && scene.objects[static_cast<size_t>(hit.object)].material.receives_caustics()) return true;
    ray = tracer.spawn(hit, ray.direction);
  }
  return false;
}

}  // namespace causticbench
