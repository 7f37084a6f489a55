#include "core/sampling.h"

#include <algorithm>

namespace causticbench {

Distribution1D::Distribution1D(const std::vector<double>& weights) : weights_(weights), cdf_(weights.size() + 1) {
  cdf_[0] = 0.0;
  for (size_t i = 0; i < weights_.size(); ++i) cdf_[i + 1] = cdf_[i] + std::max(0.0, weights_[i]);
  total_ = cdf_.back();
}

size_t Distribution1D::sample(double u, double& probability) const {
  double target = u * total_;
  auto it = std::upper_bound(cdf_.begin(), cdf_.end(), target);
  size_t index = std::min<size_t>(std::max<ptrdiff_t>(0, (it - cdf_.begin()) - 1), weights_.size() - 1);
  // Skip zero-weight entries that upper_bound can land on at their boundary.
  while (index + 1 < weights_.size() && weights_[index] <= 0.0) ++index;
  probability = weights_[index] / total_;
  return index;
}

}  // namespace causticbench
