// Random numbers and the warps the photon tracer and the methods draw from. Every random choice in
// causticbench comes from a Random seeded by (seed, stream), so that output is reproducible.
#pragma once

#include <cstdint>
#include <vector>

#include <pcg_random.hpp>

#include "core/math.h"

namespace causticbench {

class Random {
 public:
  Random(uint64_t seed, uint64_t stream) : generator_(seed, stream) {}
  // Uniform in [0, 1).
  float uniform() { return std::min(static_cast<float>(generator_() >> 8) * 0x1p-24f, 0x1.fffffep-1f); }
  double uniform_double() {
    uint64_t bits = (static_cast<uint64_t>(generator_()) << 21) ^ generator_();
    return static_cast<double>(bits & ((1ull << 53) - 1)) * 0x1p-53;
  }
  uint32_t next() { return generator_(); }

 private:
  pcg32 generator_;
};

// Shirley-Chiu concentric map from the unit square to the unit disk.
inline void sample_disk(float u1, float u2, float& x, float& y) {
  float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
  if (a == 0.0f && b == 0.0f) {
    x = y = 0.0f;
    return;
  }
  float r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (kPi / 4.0f) * (b / a);
  } else {
    r = b;
    phi = kPi / 2.0f - (kPi / 4.0f) * (a / b);
  }
  x = r * std::cos(phi);
  y = r * std::sin(phi);
}

// Direction uniform in solid angle inside the cone of half-angle acos(cos_max) around `axis`.
inline Vec3 sample_cone(const Vec3& axis, float cos_max, float u1, float u2) {
  float cos_theta = 1.0f - u1 * (1.0f - cos_max);
  float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  float phi = 2.0f * kPi * u2;
  Vec3 t, b;
  orthonormal_basis(axis, t, b);
  return glm::normalize(t * (sin_theta * std::cos(phi)) + b * (sin_theta * std::sin(phi)) + axis * cos_theta);
}

inline Vec3 sample_sphere(float u1, float u2) {
  float z = 1.0f - 2.0f * u1;
  float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  float phi = 2.0f * kPi * u2;
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// Cosine-weighted direction on the hemisphere around n.
inline Vec3 sample_cosine_hemisphere(const Vec3& n, float u1, float u2) {
  float x, y;
  sample_disk(u1, u2, x, y);
  float z = std::sqrt(std::max(0.0f, 1.0f - x * x - y * y));
  Vec3 t, b;
  orthonormal_basis(n, t, b);
  return glm::normalize(t * x + b * y + n * z);
}

// A piecewise-constant 1D distribution for importance sampling (tabulated CDF).
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(const std::vector<double>& weights);
  // Returns the index and sets pdf to its probability mass; u in [0, 1).
  size_t sample(double u, double& probability) const;
  double probability(size_t index) const { return total_ > 0.0 ? weights_[index] / total_ : 0.0; }
  double total() const { return total_; }
  size_t size() const { return weights_.size(); }

 private:
  std::vector<double> weights_;
  std::vector<double> cdf_;
  double total_ = 0.0;
};

}  // namespace causticbench
