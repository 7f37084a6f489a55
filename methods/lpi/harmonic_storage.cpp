#include "methods/lpi/harmonic_storage.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "core/parallel.h"
#include "methods/common/spherical_harmonics.h"

namespace causticbench::lpi {

std::vector<double> light_sample_areas(const LightSampleSet& set) {
  if (!set.mesh) throw std::invalid_argument("light_sample_areas: the set has no triangulation (not geodesic)");
  const std::vector<Vec3>& points = set.mesh->points();
  std::vector<double> areas(points.size(), 0.0);
  for (const auto& triangle : set.mesh->triangles()) {
    const glm::dvec3 a = glm::normalize(glm::dvec3(points[triangle[0]])), b = glm::normalize(glm::dvec3(points[triangle[1]])),
                     c = glm::normalize(glm::dvec3(points[triangle[2]]));
    const double third = solid_angle(a, b, c) / 3.0;
    for (uint32_t corner : triangle) areas[corner] += third;
  }
  return areas;
}

HarmonicFit::HarmonicFit(int order, const std::vector<Vec3>& directions, const std::vector<double>& weights)
    : bands_(order + 1), samples_(directions.size()) {
  const int n = coefficient_count(bands_);
  if (directions.size() != weights.size()) throw std::invalid_argument("HarmonicFit: a weight per direction");
  if (directions.size() < static_cast<size_t>(n)) {
    throw std::invalid_argument(fmt::format("sh_order {} has {} coefficients, more than the {} light samples can determine; "
                                            "raise light_subdivision or lower sh_order",
                                            order, n, directions.size()));
  }
  // basis: samples x n; gram = Y^T W Y (n x n), solved by Cholesky.
  std::vector<double> basis(samples_ * n);
  for (size_t i = 0; i < samples_; ++i) evaluate(bands_, glm::normalize(glm::dvec3(directions[i])), basis.data() + i * n);
  std::vector<double> gram(static_cast<size_t>(n) * n, 0.0);
  for (size_t i = 0; i < samples_; ++i) {
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) gram[j * n + k] += weights[i] * basis[i * n + j] * basis[i * n + k];
  }
  // In place: gram = L L^T, L in the lower triangle. A pivot below 1e-9 of the diagonal's scale (4 pi
  // x the mean of Y^2, 1) means the samples leave a combination of the basis undetermined.
  for (int j = 0; j < n; ++j) {
    double pivot = gram[j * n + j];
    for (int k = 0; k < j; ++k) pivot -= gram[j * n + k] * gram[j * n + k];
    if (!(pivot > 1e-9)) {
      throw std::invalid_argument(fmt::format("sh_order {}: the {} light samples do not determine its {} coefficients; "
                                              "raise light_subdivision or lower sh_order",
                                              order, samples_, n));
    }
    gram[j * n + j] = std::sqrt(pivot);
    for (int i = j + 1; i < n; ++i) {
      double sum = gram[i * n + j];
      for (int k = 0; k < j; ++k) sum -= gram[i * n + k] * gram[j * n + k];
      gram[i * n + j] = sum / gram[j * n + j];
    }
  }
  // solve_ column i = (L L^T)^-1 (w_i y_i).
  solve_.assign(static_cast<size_t>(n) * samples_, 0.0);
  std::vector<double> column(n);
  for (size_t i = 0; i < samples_; ++i) {
    for (int j = 0; j < n; ++j) {
      double sum = weights[i] * basis[i * n + j];
      for (int k = 0; k < j; ++k) sum -= gram[j * n + k] * column[k];
      column[j] = sum / gram[j * n + j];
    }
    for (int j = n - 1; j >= 0; --j) {
      double sum = column[j];
      for (int k = j + 1; k < n; ++k) sum -= gram[k * n + j] * column[k];
      column[j] = sum / gram[j * n + j];
    }
    for (int j = 0; j < n; ++j) solve_[j * samples_ + i] = column[j];
  }
}

std::vector<float> HarmonicFit::fit(const std::vector<float>& values, size_t per_sample) const {
  if (values.size() != per_sample * samples_) {
    throw std::logic_error(fmt::format("HarmonicFit::fit: {} values for {} samples of {}", values.size(), samples_, per_sample));
  }
  const int n = coefficients();
  std::vector<float> fitted(static_cast<size_t>(n) * per_sample);
  // Each output sums its samples in sample order, whatever block computes it: thread-count independent.
  parallel_blocks(per_sample, 4096, [&](size_t begin, size_t end, size_t) {
    std::vector<double> sums(static_cast<size_t>(n) * (end - begin), 0.0);
    for (size_t i = 0; i < samples_; ++i) {
      const float* block = values.data() + i * per_sample;
      for (int k = 0; k < n; ++k) {
        const double factor = solve_[k * samples_ + i];
        double* out = sums.data() + k * (end - begin);
        for (size_t v = begin; v < end; ++v) out[v - begin] += factor * block[v];
      }
    }
    for (int k = 0; k < n; ++k)
      for (size_t v = begin; v < end; ++v) fitted[k * per_sample + v] = static_cast<float>(sums[k * (end - begin) + v - begin]);
  });
  return fitted;
}

}  // namespace causticbench::lpi
