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
#include "metrics/flip.h"

namespace causticbench {

namespace {

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

// The reference's largest luminance over `valid`: SSIM's dynamic range.
double reference_luminance_peak(const Image& reference, const std::vector<uint8_t>& valid) {
  double peak = 0.0;
  for (size_t pixel = 0; pixel < valid.size(); ++pixel)
    if (valid[pixel]) peak = std::max(peak, luminance(reference, pixel));
  return peak;
}

// Mean SSIM over `valid` pixels (the mask with non-finite test pixels removed; at least one is set),
// with dynamic range `peak` > 0.
double masked_ssim(const Image& test, const Image& reference, const std::vector<uint8_t>& valid, double peak) {
  const int width = reference.width(), height = reference.height();
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

const char* const kNoValidPixel = "no receiver pixel with a finite test value";

// The valid pixels V (masked, finite test value) and the sums over them that the metrics share.
struct FrameSums {
  std::vector<uint8_t> valid;
  size_t count = 0;
  size_t nonfinite_pixels = 0;
  double squared_error = 0.0;
  double max_error = 0.0;
  double reference_peak = -kInfinity;  // largest reference channel
};

FrameSums frame_sums(const Image& test, const Image& reference, const std::vector<uint8_t>& mask) {
  FrameSums sums;
  sums.valid.assign(reference.pixel_count(), 0);
  for (size_t pixel = 0; pixel < reference.pixel_count(); ++pixel) {
    if (!mask[pixel]) continue;
    if (!pixel_finite(test, pixel)) {
      ++sums.nonfinite_pixels;
      continue;
    }
    sums.valid[pixel] = 1;
    ++sums.count;
    for (int c = 0; c < 3; ++c) {
      double difference = static_cast<double>(test.at(pixel, c)) - reference.at(pixel, c);
      sums.squared_error += difference * difference;
      sums.max_error = std::max(sums.max_error, std::abs(difference));
      sums.reference_peak = std::max(sums.reference_peak, static_cast<double>(reference.at(pixel, c)));
    }
  }
  return sums;
}

MetricValue defined(double value) { return {value, ""}; }
MetricValue undefined(const std::string& reason) { return {std::nullopt, reason}; }

MetricValue psnr(const FrameSums& sums, double mse) {
  if (!(sums.reference_peak > 0.0))
    return undefined("the reference is 0 over the receivers: PSNR has no peak to compare the error with");
  return defined(mse == 0.0 ? kInfinity : 10.0 * std::log10(sums.reference_peak * sums.reference_peak / mse));
}

MetricValue relmse(const Image& test, const Image& reference, const FrameSums& sums) {
  if (masked_mean(reference, sums.valid) == 0.0)
    return undefined("the reference is 0 over the receivers: relMSE has no scale (its epsilon is 0.1 x the "
                     "reference's mean)");
  return defined(relative_mse(test, reference, sums.valid));
}

MetricValue energy_ratio(const Image& test, const Image& reference, const FrameSums& sums) {
  double reference_sum = masked_sum(reference, sums.valid);
  if (reference_sum == 0.0)
    return undefined("the reference's caustic flux over the receivers is 0: no ratio (0/0 or x/0)");
  return defined(masked_sum(test, sums.valid) / reference_sum);
}

MetricValue ssim(const Image& test, const Image& reference, const FrameSums& sums) {
  double peak = reference_luminance_peak(reference, sums.valid);
  if (!(peak > 0.0))
    return undefined("the reference is 0 over the receivers: SSIM has no dynamic range to normalise by");
  return defined(masked_ssim(test, reference, sums.valid, peak));
}

// HDR-FLIP over the mask; the exposures it chose go into `parameters`, since the value depends on them.
MetricValue flip(const Image& test, const Image& reference, const std::vector<uint8_t>& mask,
                 std::map<std::string, double>& parameters) {
  const FlipOptions options;
  CausticFlip result = caustic_flip(test, reference, mask, options);
  if (!result.defined()) return undefined(result.undefined_reason);
  parameters = {{"pixels_per_degree", options.pixels_per_degree},
                {"start_exposure", result.exposures.start},
                {"stop_exposure", result.exposures.stop},
                {"exposures", result.exposures.count}};
  return defined(result.mean);
}

MetricValue frame_metric(const std::string& name, const Image& test, const Image& reference,
                         const std::vector<uint8_t>& mask, const FrameSums& sums,
                         std::map<std::string, std::map<std::string, double>>& parameters) {
  if (name == "nonfinite_pixels") return defined(static_cast<double>(sums.nonfinite_pixels));
  if (sums.count == 0) return undefined(kNoValidPixel);
  if (name == "flip") {
    std::map<std::string, double> used;
    MetricValue value = flip(test, reference, mask, used);
    if (value.value) parameters[name] = used;
    return value;
  }
  const double mse = sums.squared_error / (3.0 * static_cast<double>(sums.count));
  if (name == "mse") return defined(mse);
  if (name == "rmse") return defined(std::sqrt(mse));
  if (name == "max_error") return defined(sums.max_error);
  if (name == "psnr") return psnr(sums, mse);
  if (name == "relmse") return relmse(test, reference, sums);
  if (name == "energy_ratio") return energy_ratio(test, reference, sums);
  if (name == "ssim") return ssim(test, reference, sums);
  throw std::logic_error("metrics: no rule computes the per-frame metric '" + name + "'");
}

}  // namespace

// What a metric of images of float values can be at most (the record check's bounds, MetricInfo::maximum):
// every finite channel lies in [-FLT_MAX, FLT_MAX] (E_c is non-negative, but a plugin's image may not
// be, and its run must still be stored as measured), a reference's positive one is at least the
// smallest denormal, and an image has at most 16384^2 pixels (core/camera.cpp's resolution limit) of 3
// channels. So a reference's positive mean is at least denorm_min / (3 N), relMSE's eps at least a
// hundredth of its square, an error at most 2 FLT_MAX, and a nonzero mse at least denorm_min^2 / (3 N).
constexpr double kLargestValue = std::numeric_limits<float>::max();
constexpr double kSmallestValue = std::numeric_limits<float>::denorm_min();
constexpr double kMostChannels = 3.0 * 16384.0 * 16384.0;
constexpr double kSmallestMean = kSmallestValue / kMostChannels;
constexpr double kLargestError = 2.0 * kLargestValue;
const double kMostPsnr = 10.0 * std::log10(kLargestValue / kSmallestValue * kLargestValue / kSmallestValue * kMostChannels);
const double kLeastPsnr = 10.0 * std::log10(kSmallestValue / kLargestError * kSmallestValue / kLargestError);
// SSIM is computed in float by OpenCV: a few units in the last place beyond [-1, 1].
constexpr double kSsimSlack = 1e-5;

const std::vector<MetricInfo>& metric_registry() {
  static const std::vector<MetricInfo> registry = {
      {"mse", false, std::nullopt, "(W/m^2)^2", "mean over masked finite pixels and RGB channels of (test - reference)^2",
       true, 0.0, kLargestError * kLargestError},
      {"rmse", false, std::nullopt, "W/m^2", "square root of mse", true, 0.0, kLargestError},
      {"psnr", true, std::nullopt, "dB",
       "10 log10(peak^2 / mse), peak = largest reference channel value over the mask; +inf when mse = 0; undefined "
       "when peak = 0",
       true, kLeastPsnr, kMostPsnr},
      {"ssim", true, std::nullopt, "",
       "mean over masked finite pixels of the SSIM map (OpenCV, 11x11 Gaussian sigma 1.5) of Rec. 709 luminance, "
       "dynamic range = the reference's largest masked luminance; undefined when that is 0",
       true, -1.0 - kSsimSlack, 1.0 + kSsimSlack},
      {"relmse", false, std::nullopt, "",
       "mean over masked finite pixels and RGB channels of (test - reference)^2 / (reference^2 + eps), "
       "eps = (0.1 mean reference)^2; undefined when that mean is 0",
       true, 0.0, kLargestError * kLargestError / (0.01 * kSmallestMean * kSmallestMean)},
      {"energy_ratio", false, 1.0, "",
       "sum of test over masked finite pixels / sum of reference over them (channel mean); best is closest to 1; "
       "undefined when the reference's sum is 0",
       true, -kLargestValue / kSmallestMean, kLargestValue / kSmallestMean},
      {"max_error", false, std::nullopt, "W/m^2",
       "largest |test - reference| over masked finite pixels and RGB channels", true, 0.0, kLargestError},
      {"flip", false, std::nullopt, "",
       "mean over masked finite pixels of the HDR-FLIP map (NVIDIA FLIP v1.6, ACES, 67 ppd), exposures from the "
       "reference's masked max and lit median luminance; undefined when that max is 0",
       true, 0.0, 1.0},
      {"temporal_flicker", false, std::nullopt, "",
       "mean over frames t>=1 of masked mean |(test_t - test_t-1) - (reference_t - reference_t-1)|, divided by "
       "the reference's masked mean over all frames; undefined when that mean is 0",
       false, 0.0, 2.0 * kLargestError / kSmallestMean},
      {"nonfinite_pixels", false, std::nullopt, "pixels",
       "number of masked test pixels with a NaN or infinite channel (excluded from the other metrics)", true, 0.0,
       kMostChannels / 3.0},
  };
  return registry;
}

const MetricInfo* metric_info(const std::string& name) {
  for (const MetricInfo& metric : metric_registry())
    if (metric.name == name) return &metric;
  return nullptr;
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

  const FrameSums sums = frame_sums(test, reference, mask);
  MetricValues result;
  result.nonfinite_pixels = sums.nonfinite_pixels;
  for (const std::string& name : names) {
    MetricValue value = frame_metric(name, test, reference, mask, sums, result.parameters);
    if (value.value)
      result.values[name] = *value.value;
    else
      result.undefined[name] = value.undefined_reason;
  }
  result.values["nonfinite_pixels"] = static_cast<double>(result.nonfinite_pixels);
  return result;
}

MetricValue temporal_flicker(const std::vector<Image>& test, const std::vector<Image>& reference,
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
  if (reference.size() < 2) return undefined("flicker needs at least two frames");

  // Denominator: mean of the reference over every masked pixel of every frame.
  double reference_sum = 0.0;
  size_t reference_count = 0;
  for (size_t t = 0; t < reference.size(); ++t) {
    reference_sum += masked_sum(reference[t], masks[t]);
    for (uint8_t m : masks[t]) reference_count += m ? 1 : 0;
  }
  if (reference_count == 0) return undefined("no receiver pixel in any frame");
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
  if (frame_count == 0)
    return undefined("no pair of consecutive frames shares a receiver pixel with finite test values");
  if (reference_mean == 0.0)
    return undefined("the reference is 0 over the receivers of every frame: flicker has no scale");
  return defined(frame_sum / static_cast<double>(frame_count) / reference_mean);
}

}  // namespace causticbench
