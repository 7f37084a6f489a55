// The fraction of the light's radiance a reflector sample carries towards a receiver, as a function of
// the cosine at the sample: reflectance (conductor or dielectric Fresnel, or constant), or for refraction
// the transmittance times the radiance compression n^2. ThroughputTable holds it per material for the
// unfiltered reflection kernel: the complex conductor Fresnel per channel and pair was 29 % of an
// environment-map render (issue 16), a table lookup is two loads and a blend.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/material.h"
#include "core/optics.h"

namespace causticbench {

struct Interaction {
  bool refract = false;
  bool fresnel = true;  // false: the reflectance at normal incidence for every cosine
};

inline Color light_throughput(const Material& material, const Interaction& interaction, float cos_sample) {
  float cosine = interaction.fresnel ? cos_sample : 1.0f;
  if (interaction.refract) {
    return Color((1.0f - fresnel_dielectric(cosine, 1.0f / material.ior)) * material.ior * material.ior);
  }
  if (material.kind == MaterialKind::glass) return Color(fresnel_dielectric(cosine, material.ior));
  return material.mirror_reflectance(cosine);
}

// light_throughput of one material for reflection, tabulated at kEntries cosines uniformly over [0, 1]
// and interpolated linearly. Reflection only: refraction has a kink at the critical angle (total
// internal reflection) that a linear table would round off. The largest deviation from the exact value
// over a grid 16 times finer is measured when the table is made (max_error(); below 1e-5 for the
// shipped metals and glass, methods/pinhole/tests/test_pinhole.cpp).
class ThroughputTable {
 public:
  static constexpr int kEntries = 1024;

  ThroughputTable(const Material& material, bool fresnel) : material_(&material) {
    const Interaction reflect{false, fresnel};
    values_.resize(kEntries + 1);  // one past the end, so that the blend at cosine 1 needs no branch
    for (int i = 0; i < kEntries; ++i)
      values_[i] = light_throughput(material, reflect, static_cast<float>(i) / (kEntries - 1));
    values_[kEntries] = values_[kEntries - 1];
    const int fine = 16 * (kEntries - 1);
    for (int i = 0; i <= fine; ++i) {
      float cosine = static_cast<float>(i) / fine;
      Color difference = (*this)(cosine) - light_throughput(material, reflect, cosine);
      max_error_ = std::max({max_error_, std::abs(difference.r), std::abs(difference.g), std::abs(difference.b)});
    }
  }

  Color operator()(float cosine) const {
    float position = std::clamp(cosine, 0.0f, 1.0f) * (kEntries - 1);
    int index = static_cast<int>(position);
    float fraction = position - static_cast<float>(index);
    return values_[index] + (values_[index + 1] - values_[index]) * fraction;
  }

  const Material* material() const { return material_; }
  const std::vector<Color>& values() const { return values_; }  // kEntries + 1 (the last repeated)
  float max_error() const { return max_error_; }

 private:
  const Material* material_;
  std::vector<Color> values_;
  float max_error_ = 0.0f;
};

}  // namespace causticbench
