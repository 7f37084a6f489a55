// The first surface along a ray that receives caustics: what a light pass sees once its mirrors and
// glass are looked through (caustic_mapping's receiver map and its exact searches), and where a beam's
// light lands when nothing inside it is modelled as blocking (caustic_volume's far-cap check).
#pragma once

#include "core/tracer.h"

namespace causticbench {

// The first surface along `ray` that receives caustics and is not object `skip`: specular surfaces (and
// `skip`) are passed through; false when there is none. A diffuse mirror other than `skip` receives.
bool first_receiver(const Tracer& tracer, Ray ray, SurfaceHit& hit, int skip = -1);

}  // namespace causticbench
