#include "core/image_statistics.h"

namespace causticbench {

double masked_sum(const Image& image, const std::vector<uint8_t>& mask) {
  double sum = 0.0;
  for (size_t pixel = 0; pixel < image.pixel_count(); ++pixel) {
    if (!mask[pixel]) continue;
    for (int c = 0; c < 3; ++c) sum += image.at(pixel, c);
  }
  return sum / 3.0;
}

double masked_mean(const Image& image, const std::vector<uint8_t>& mask) {
  size_t count = 0;
  for (uint8_t m : mask) count += m ? 1 : 0;
  return count ? masked_sum(image, mask) / static_cast<double>(count) : 0.0;
}

double relative_mse_epsilon(double mean) {
  double epsilon = (0.1 * mean) * (0.1 * mean);
  return epsilon > 0.0 ? epsilon : 1e-20;
}

double relative_mse(const Image& test, const Image& reference, const std::vector<uint8_t>& mask) {
  const double epsilon = relative_mse_epsilon(masked_mean(reference, mask));
  double sum = 0.0;
  size_t count = 0;
  for (size_t pixel = 0; pixel < test.pixel_count(); ++pixel) {
    if (!mask[pixel]) continue;
    for (int c = 0; c < 3; ++c) {
      double difference = static_cast<double>(test.at(pixel, c)) - reference.at(pixel, c);
      double value = reference.at(pixel, c);
      sum += difference * difference / (value * value + epsilon);
    }
    ++count;
  }
  return count ? sum / (3.0 * static_cast<double>(count)) : 0.0;
}

}  // namespace causticbench
