#include "metrics/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

// OpenCV 4.6's headers mix enumeration types, which C++20 deprecates; keep that noise out of the build.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-enum-enum-conversion"
#include <opencv2/core.hpp>
#include <opencv2/quality.hpp>
#pragma GCC diagnostic pop

#include "core/errors.h"
#include "core/image_statistics.h"

namespace causticbench {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Rec. 709 / sRGB luminance weights.
constexpr double kLuminance[3] = {0.2126, 0.7152, 0.0722};

// OpenCV's QualitySSIM hard-codes C1 = (0.01 * 255)^2 and C2 = (0.03 * 255)^2, the constants of the SSIM
// paper for a dynamic range of 255. Scaling the normalised images (range 1) by 255 makes them the paper's
// constants for a dynamic range equal to the reference's maximum luminance.
constexpr double kOpenCvSsimRange = 255.0;

bool pixel_finite(const Image& image, size_t pixel) {
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(image.at(pixel, c))) return false;
  return true;
}

void check_image(const Image& image, const Image& reference, const char* what) {
  if (image.width() != reference.width() || image.height() != reference.height())
    throw std::invalid_argument(std::string("metrics: ") + what + " is " + std::to_string(image.width()) + "x" +
                                std::to_string(image.height()) + " but the reference is " +
                                std::to_string(reference.width()) + "x" + std::to_string(reference.height()));
  if (image.channels() < 3 || reference.channels() < 3)
    throw std::invalid_argument(std::string("metrics: ") + what + " and reference need at least 3 channels");
}

void check_mask(const std::vector<uint8_t>& mask, const Image& image) {
  if (mask.size() != image.pixel_count())
    throw std::invalid_argument("metrics: the mask has " + std::to_string(mask.size()) + " entries for " +
                                std::to_string(image.pixel_count()) + " pixels");
}

void check_reference_finite(const Image& reference, const std::vector<uint8_t>& mask) {
  for (size_t pixel = 0; pixel < reference.pixel_count(); ++pixel) {
    if (mask[pixel] && !pixel_finite(reference, pixel)) {
      size_t x = pixel % static_cast<size_t>(reference.width());
      size_t y = pixel / static_cast<size_t>(reference.width());
      throw std::invalid_argument("metrics: the reference has a non-finite value at masked pixel (" +
                                  std::to_string(x) + ", " + std::to_string(y) + ")");
    }
  }
}

double luminance(const Image& image, size_t pixel) {
  return kLuminance[0] * image.at(pixel, 0) + kLuminance[1] * image.at(pixel, 1) +
         kLuminance[2] * image.at(pixel, 2);
}

// Mean SSIM over `valid` pixels (the mask with non-finite test pixels removed; at least one is set).
double masked_ssim(const Image& test, const Image& reference, const std::vector<uint8_t>& valid) {
  const int width = reference.width(), height = reference.height();
  double reference_peak = 0.0, test_peak = 0.0;
  for (size_t pixel = 0; pixel < valid.size(); ++pixel) {
    if (!valid[pixel]) continue;
    reference_peak = std::max(reference_peak, luminance(reference, pixel));
    test_peak = std::max(test_peak, luminance(test, pixel));
  }
  // A black reference has no range of its own: fall back to the test's, and two black images are identical.
  double peak = reference_peak > 0.0 ? reference_peak : test_peak;
  if (!(peak > 0.0)) return 1.0;
  const double scale = kOpenCvSsimRange / peak;

  cv::Mat reference_luminance(height, width, CV_64F, cv::Scalar(0.0));
  cv::Mat test_luminance(height, width, CV_64F, cv::Scalar(0.0));
  for (int y = 0; y < height; ++y) {
    double* r = reference_luminance.ptr<double>(y);
    double* t = test_luminance.ptr<double>(y);
    for (int x = 0; x < width; ++x) {
      size_t pixel = static_cast<size_t>(y) * width + x;
      if (!valid[pixel]) continue;  // outside the mask or non-finite: 0 in both images
      r[x] = scale * luminance(reference, pixel);
      t[x] = scale * luminance(test, pixel);
    }
  }

  cv::Mat quality_map;
  cv::quality::QualitySSIM::compute(reference_luminance, test_luminance, quality_map);
  cv::Mat map;
  quality_map.convertTo(map, CV_64F);

  double sum = 0.0;
  size_t count = 0;
  for (int y = 0; y < height; ++y) {
    const double* m = map.ptr<double>(y);
    for (int x = 0; x < width; ++x) {
      if (!valid[static_cast<size_t>(y) * width + x]) continue;
      sum += m[x];
      ++count;
    }
  }
  return sum / static_cast<double>(count);
}

}  // namespace

const std::vector<MetricInfo>& metric_registry() {
  static const std::vector<MetricInfo> registry = {
      {"mse", false, std::nullopt, "(W/m^2)^2", "mean over masked finite pixels and RGB channels of (test - reference)^2",
       true},
      {"rmse", false, std::nullopt, "W/m^2", "square root of mse", true},
      {"psnr", true, std::nullopt, "dB",
       "10 log10(peak^2 / mse), peak = largest reference channel value over the mask; +inf when mse = 0", true},
      {"ssim", true, std::nullopt, "",
       "mean over masked finite pixels of the SSIM map (OpenCV, 11x11 Gaussian sigma 1.5) of Rec. 709 luminance, "
       "dynamic range = the reference's largest masked luminance",
       true},
      {"relmse", false, std::nullopt, "",
       "mean over masked finite pixels and RGB channels of (test - reference)^2 / (reference^2 + eps), "
       "eps = (0.1 mean reference)^2",
       true},
      {"energy_ratio", false, 1.0, "",
       "sum of test over masked finite pixels / sum of reference over them (channel mean); best is closest to 1",
       true},
      {"max_error", false, std::nullopt, "W/m^2",
       "largest |test - reference| over masked finite pixels and RGB channels", true},
      {"temporal_flicker", false, std::nullopt, "",
       "mean over frames t>=1 of masked mean |(test_t - test_t-1) - (reference_t - reference_t-1)|, divided by "
       "the reference's masked mean over all frames",
       false},
      {"nonfinite_pixels", false, std::nullopt, "pixels",
       "number of masked test pixels with a NaN or infinite channel (excluded from the other metrics)", true},
  };
  return registry;
}

const MetricInfo& find_metric(const std::string& name) {
  const auto& registry = metric_registry();
  for (const MetricInfo& metric : registry)
    if (metric.name == name) return metric;
  std::vector<std::string> names;
  for (const MetricInfo& metric : registry) names.push_back(metric.name);
  throw InputError("unknown metric '" + name + "'" + did_you_mean(name, names) + "; known metrics: " +
                   join(names, ", "));
}

bool metric_better(const MetricInfo& metric, double a, double b) {
  if (std::isnan(a)) return false;
  if (std::isnan(b)) return true;
  if (metric.target) return std::abs(a - *metric.target) < std::abs(b - *metric.target);
  return metric.higher_is_better ? a > b : a < b;
}

MetricValues compute_metrics(const Image& test, const Image& reference, const std::vector<uint8_t>& mask,
                             const std::vector<std::string>& names) {
  for (const std::string& name : names) {
    const MetricInfo& metric = find_metric(name);
    if (!metric.per_frame)
      throw InputError("metric '" + name + "' needs a sequence of frames and is not a per-frame metric");
  }
  check_image(test, reference, "the test image");
  check_mask(mask, reference);
  check_reference_finite(reference, mask);

  MetricValues result;
  const size_t pixels = reference.pixel_count();
  std::vector<uint8_t> valid(pixels, 0);
  size_t count = 0;
  double squared_error = 0.0, max_error = 0.0, peak = -kInfinity;
  for (size_t pixel = 0; pixel < pixels; ++pixel) {
    if (!mask[pixel]) continue;
    if (!pixel_finite(test, pixel)) {
      ++result.nonfinite_pixels;
      continue;
    }
    valid[pixel] = 1;
    ++count;
    for (int c = 0; c < 3; ++c) {
      double difference = static_cast<double>(test.at(pixel, c)) - reference.at(pixel, c);
      squared_error += difference * difference;
      max_error = std::max(max_error, std::abs(difference));
      peak = std::max(peak, static_cast<double>(reference.at(pixel, c)));
    }
  }

  const double mse = count ? squared_error / (3.0 * static_cast<double>(count)) : kNaN;
  for (const std::string& name : names) {
    double value = kNaN;
    if (count == 0) {
      value = kNaN;
    } else if (name == "mse") {
      value = mse;
    } else if (name == "rmse") {
      value = std::sqrt(mse);
    } else if (name == "max_error") {
      value = max_error;
    } else if (name == "psnr") {
      value = mse == 0.0 ? kInfinity : 10.0 * std::log10(peak * peak / mse);
    } else if (name == "relmse") {
      value = relative_mse(test, reference, valid);
    } else if (name == "energy_ratio") {
      double test_sum = masked_sum(test, valid), reference_sum = masked_sum(reference, valid);
      if (reference_sum != 0.0)
        value = test_sum / reference_sum;
      else
        value = test_sum == 0.0 ? 1.0 : std::copysign(kInfinity, test_sum);
    } else if (name == "ssim") {
      value = masked_ssim(test, reference, valid);
    }
    result.values[name] = value;
  }
  result.values["nonfinite_pixels"] = static_cast<double>(result.nonfinite_pixels);
  return result;
}

double temporal_flicker(const std::vector<Image>& test, const std::vector<Image>& reference,
                        const std::vector<std::vector<uint8_t>>& masks) {
  if (test.size() != reference.size() || masks.size() != reference.size())
    throw std::invalid_argument("temporal_flicker: " + std::to_string(test.size()) + " test frames, " +
                                std::to_string(reference.size()) + " reference frames and " +
                                std::to_string(masks.size()) + " masks");
  for (size_t t = 0; t < reference.size(); ++t) {
    check_image(test[t], reference[t], "a test frame");
    check_image(reference[t], reference[0], "a reference frame");
    check_mask(masks[t], reference[t]);
    check_reference_finite(reference[t], masks[t]);
  }
  if (reference.size() < 2) return kNaN;

  // Denominator: mean of the reference over every masked pixel of every frame.
  double reference_sum = 0.0;
  size_t reference_count = 0;
  for (size_t t = 0; t < reference.size(); ++t) {
    reference_sum += masked_sum(reference[t], masks[t]);
    for (uint8_t m : masks[t]) reference_count += m ? 1 : 0;
  }
  if (reference_count == 0) return kNaN;
  const double reference_mean = reference_sum / static_cast<double>(reference_count);

  double frame_sum = 0.0;
  size_t frame_count = 0;
  for (size_t t = 1; t < reference.size(); ++t) {
    const Image &a1 = test[t], &a0 = test[t - 1], &r1 = reference[t], &r0 = reference[t - 1];
    double sum = 0.0;
    size_t count = 0;
    for (size_t pixel = 0; pixel < r1.pixel_count(); ++pixel) {
      if (!masks[t][pixel] || !masks[t - 1][pixel] || !pixel_finite(a1, pixel) || !pixel_finite(a0, pixel))
        continue;
      for (int c = 0; c < 3; ++c) {
        double method_change = static_cast<double>(a1.at(pixel, c)) - a0.at(pixel, c);
        double reference_change = static_cast<double>(r1.at(pixel, c)) - r0.at(pixel, c);
        sum += std::abs(method_change - reference_change);
      }
      ++count;
    }
    if (count == 0) continue;  // no pixel in common: this frame pair says nothing
    frame_sum += sum / (3.0 * static_cast<double>(count));
    ++frame_count;
  }
  if (frame_count == 0) return kNaN;
  const double flicker = frame_sum / static_cast<double>(frame_count);
  if (reference_mean == 0.0) return flicker == 0.0 ? 0.0 : kInfinity;
  return flicker / reference_mean;
}

}  // namespace causticbench
