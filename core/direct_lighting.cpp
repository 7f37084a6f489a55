#include "core/direct_lighting.h"

#include "core/parallel.h"
#include "core/sampling.h"

namespace causticbench {

Image direct_irradiance(const Tracer& tracer, const GBuffer& gbuffer, int samples, uint64_t seed) {
  const SceneFrame& frame = tracer.frame();
  Image result(gbuffer.width, gbuffer.height, 3);
  parallel_blocks(gbuffer.pixel_count(), 1024, [&](size_t begin, size_t end, size_t) {
    for (size_t pixel = begin; pixel < end; ++pixel) {
      if (!gbuffer.receiver[pixel]) continue;
      Random random(seed, pixel);
      Vec3 normal = gbuffer.normal[pixel];
      Vec3 origin = gbuffer.position[pixel] + normal * tracer.epsilon();
      Color sum(0.0f);
      for (const LightFrame& light : frame.lights) {
        bool single = light.kind == LightKind::directional && light.cos_cone >= 1.0f;
        int count = single || (light.kind == LightKind::point && light.radius <= 0.0f) ? 1 : samples;
        Color light_sum(0.0f);
        for (int s = 0; s < count; ++s) {
          if (light.kind == LightKind::point) {
            Vec3 position = light.sample_position(random.uniform(), random.uniform());
            Vec3 offset = position - origin;
            float distance = glm::length(offset);
            Vec3 direction = offset / distance;
            float cosine = glm::dot(normal, direction);
            if (cosine <= 0.0f || tracer.occluded(origin, direction, distance * (1.0f - 1e-4f))) continue;
            light_sum += light.light->intensity * (cosine / (distance * distance));
          } else {
            Color weight;
            Vec3 direction = light.sample_direction(random.uniform(), random.uniform(), random.uniform(), weight);
            float cosine = glm::dot(normal, direction);
            if (cosine <= 0.0f || tracer.occluded(origin, direction, 1e30f)) continue;
            light_sum += weight * cosine;
          }
        }
        sum += light_sum / static_cast<float>(count);
      }
      result.set_rgb(pixel, sum);
    }
  });
  return result;
}

Image composite_radiance(const GBuffer& gbuffer, const Image& direct, const Image& caustic) {
  Image result(gbuffer.width, gbuffer.height, 3);
  for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
    result.set_rgb(pixel, gbuffer.albedo[pixel] / kPi * (direct.rgb(pixel) + caustic.rgb(pixel)));
  }
  return result;
}

}  // namespace causticbench
