// Direct irradiance (light that reaches a point with no specular interaction) at the G-buffer points.
// Not part of the caustic quantity: it only makes the composite picture a person looks at,
// albedo / pi * (E_direct + E_caustic).
#pragma once

#include <cstdint>

#include "core/gbuffer.h"
#include "core/image.h"

namespace causticbench {

// `samples` light samples per pixel and light (area and environment lights); glass casts full shadows
// because light through it is caustic light.
Image direct_irradiance(const Tracer& tracer, const GBuffer& gbuffer, int samples, uint64_t seed);

// albedo / pi * (direct + caustic): outgoing radiance of the diffuse part.
Image composite_radiance(const GBuffer& gbuffer, const Image& direct, const Image& caustic);

}  // namespace causticbench
