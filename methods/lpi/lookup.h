// lpi's per-pixel work (Wyman 2003, Section 5.1, step 2, and Section 5.2): map the receiver point
// into the object's build space, read the light samples the frame chose through the layout's
// interpolation, correct for the receiver's orientation, scale by the light. A template over the
// layout so that its stencil inlines.
#pragma once

#include <vector>

#include "core/gbuffer.h"
#include "core/image.h"
#include "methods/lpi/grid_layout.h"
#include "methods/lpi/light_samples.h"
#include "methods/lpi/multires_layout.h"
#include "methods/lpi/precompute.h"
#include "methods/lpi/shell_layout.h"

namespace causticbench::lpi {

// One light as one object sees it this frame: its reads of the object's light samples and its
// irradiance colour (a point light's at the object's centre).
struct LightView {
  LightReads reads;
  Color irradiance{0.0f};
  // storage: sh: the basis at the light's direction, one weight per coefficient block (reads unused).
  std::vector<float> harmonics;
};

enum class Outside { clamp, fade, zero };

// One object this frame: its map into build space and its lights' reads.
struct ObjectFrame {
  BuildSpaceMap map;
  std::vector<LightView> lights;
};

struct ObjectView {
  const StoredValues& values;
  const BuildSpaceMap& map;
  const LightView* lights;
  size_t light_count;
  Outside outside;
};

// The receiver's share of values read at one point: the paper orientation's cosine, or the vector
// irradiance dotted with the normal.
inline void add_shading(const float* values, const Vec3& normal, bool vector, float paper_cosine, float* sums) {
  if (!vector) {
    for (int c = 0; c < 3; ++c) sums[c] += values[c] * paper_cosine;
  } else {
    for (int c = 0; c < 3; ++c) sums[c] += normal.x * values[3 * c] + normal.y * values[3 * c + 1] + normal.z * values[3 * c + 2];
  }
}

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
      if (!light.harmonics.empty()) {
        // One stencil; each of its points sums its coefficients times the basis.
        const Stencil stencil = layout.stencil(center + offset);
        float values[9] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
        for (int s = 0; s < stencil.count; ++s) {
          for (size_t k = 0; k < light.harmonics.size(); ++k) {
            view.values.add(k, stencil.points[s], stencil.weights[s] * light.harmonics[k], values);
          }
        }
        add_shading(values, normal, vector, paper_cosine, sums);
      }
      for (int r = 0; r < light.reads.count; ++r) {
        const SampleRead& read = light.reads.reads[r];
        const Stencil stencil = layout.stencil(center + (read.rotated ? read.rotation * offset : offset));
        float values[9] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
        for (int s = 0; s < stencil.count; ++s) {
          view.values.add(read.sample, stencil.points[s], stencil.weights[s] * read.weight, values);
        }
        // Vector irradiance read at R p is R E(p): dot it with R n.
        add_shading(values, read.rotated ? read.rotation * normal : normal, vector, paper_cosine, sums);
      }
      for (int c = 0; c < 3; ++c) total[c] += std::max(0.0f, sums[c]) * light.irradiance[c] * fade;
    }
    const Color before(result.at(pixel, 0), result.at(pixel, 1), result.at(pixel, 2));
    result.set_rgb(pixel, before + total);
  }
}

}  // namespace causticbench::lpi
