// lpi's per-pixel work (Wyman 2003, Section 5.1, step 2, and Section 5.2): map the receiver point
// into the object's build space, read the light samples the frame chose through the layout's
// interpolation, correct for the receiver's orientation, scale by the light. A template over the
// layout so that its stencil inlines.
#pragma once

#include "core/gbuffer.h"
#include "core/image.h"
#include "methods/lpi/grid_layout.h"
#include "methods/lpi/light_samples.h"
#include "methods/lpi/precompute.h"
#include "methods/lpi/shell_layout.h"

namespace causticbench::lpi {

// One light as one object sees it this frame: its reads of the object's light samples and its
// irradiance colour (a point light's at the object's centre).
struct LightView {
  LightReads reads;
  Color irradiance{0.0f};
};

enum class Outside { clamp, fade, zero };

struct ObjectView {
  const StoredValues& values;
  const BuildSpaceMap& map;
  const LightView* lights;
  size_t light_count;
  Outside outside;
};

// Adds one object's caustic to `result` for pixels [begin, end).
template <class Layout>
void add_object_caustic(const Layout& layout, const ObjectView& view, const GBuffer& gbuffer, size_t begin, size_t end,
                        Image& result) {
  const Vec3 center = layout.center();
  const float radius = layout.radius();
  const bool vector = view.values.channels() == 9;
  for (size_t pixel = begin; pixel < end; ++pixel) {
    if (!gbuffer.receiver[pixel]) continue;
    const Vec3 point = view.map.point(gbuffer.position[pixel]);
    const Vec3 normal = glm::normalize(view.map.normals * gbuffer.normal[pixel]);
    Vec3 offset = point - center;
    const float distance = glm::length(offset);
    float fade = 1.0f;
    if (distance > radius) {
      if (view.outside == Outside::zero) continue;
      if (view.outside == Outside::fade) fade = (radius / distance) * (radius / distance);
      offset *= radius / distance;  // the value on the ball's surface
    }
    // The paper's orientation: the stored irradiance is for a surface facing the centre.
    const float paper_cosine = distance > 0.0f ? std::max(0.0f, -glm::dot(normal, point - center) / distance) : 0.0f;
    Color total(0.0f);
    for (size_t l = 0; l < view.light_count; ++l) {
      const LightView& light = view.lights[l];
      float sums[3] = {0.0f, 0.0f, 0.0f};
      for (int r = 0; r < light.reads.count; ++r) {
        const SampleRead& read = light.reads.reads[r];
        const Stencil stencil = layout.stencil(center + (read.rotated ? read.rotation * offset : offset));
        float values[9] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
        for (int s = 0; s < stencil.count; ++s) {
          view.values.add(read.sample, stencil.points[s], stencil.weights[s] * read.weight, values);
        }
        if (!vector) {
          for (int c = 0; c < 3; ++c) sums[c] += values[c] * paper_cosine;
        } else {
          // Vector irradiance read at R p is R E(p): dot it with R n.
          const Vec3 turned = read.rotated ? read.rotation * normal : normal;
          for (int c = 0; c < 3; ++c) {
            sums[c] += turned.x * values[3 * c] + turned.y * values[3 * c + 1] + turned.z * values[3 * c + 2];
          }
        }
      }
      for (int c = 0; c < 3; ++c) total[c] += std::max(0.0f, sums[c]) * light.irradiance[c] * fade;
    }
    const Color before(result.at(pixel, 0), result.at(pixel, 1), result.at(pixel, 2));
    result.set_rgb(pixel, before + total);
  }
}

}  // namespace causticbench::lpi
