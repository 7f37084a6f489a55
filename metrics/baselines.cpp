#include "metrics/baselines.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

namespace causticbench {

const std::vector<Baseline>& baselines() {
  static const std::vector<Baseline> all = {
      {"black image", "E_c = 0 everywhere: no caustic shown"},
      {"blurred reference",
       "the reference blurred over the receivers by a Gaussian of sigma = 1/32 of the image's larger side (at least 2 "
       "pixels): the caustic's energy where it lies, none of its sharpness"}};
  return all;
}

Image black_baseline(const Image& reference) { return Image(reference.width(), reference.height(), 3); }

double baseline_blur_sigma(int width, int height) { return std::max(2.0, std::max(width, height) / 32.0); }

Image blurred_baseline(const Image& reference, const std::vector<uint8_t>& mask, double sigma) {
  const int width = reference.width(), height = reference.height();
  cv::Mat weight(height, width, CV_64F), blurred_weight;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) weight.at<double>(y, x) = mask[static_cast<size_t>(y) * width + x] ? 1.0 : 0.0;
  cv::GaussianBlur(weight, blurred_weight, cv::Size(0, 0), sigma, sigma, cv::BORDER_CONSTANT);
  Image result(width, height, 3);
  for (int c = 0; c < 3; ++c) {
    cv::Mat channel(height, width, CV_64F), blurred;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const size_t pixel = static_cast<size_t>(y) * width + x;
        channel.at<double>(y, x) = mask[pixel] ? reference.at(pixel, c) : 0.0;
      }
    cv::GaussianBlur(channel, blurred, cv::Size(0, 0), sigma, sigma, cv::BORDER_CONSTANT);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const size_t pixel = static_cast<size_t>(y) * width + x;
        const double w = blurred_weight.at<double>(y, x);
        if (mask[pixel] && w > 0.0) result.at(pixel, c) = static_cast<float>(blurred.at<double>(y, x) / w);
      }
  }
  return result;
}

std::vector<BaselineScores> score_baselines(const std::vector<Image>& references,
                                            const std::vector<std::vector<uint8_t>>& masks,
                                            const std::vector<std::string>& names) {
  std::vector<std::string> per_frame;
  bool flicker = false;
  for (const std::string& name : names) {
    const MetricInfo& info = find_metric(name);
    if (info.per_frame) per_frame.push_back(name);
    else flicker = true;
  }
  std::vector<BaselineScores> scores;
  for (const Baseline& baseline : baselines()) {
    BaselineScores score;
    score.name = baseline.name;
    score.detail = baseline.name == "black image" || references.empty()
                       ? "E_c = 0"
                       : fmt::format("Gaussian, sigma {:g} px, over the receivers",
                                     baseline_blur_sigma(references.front().width(), references.front().height()));
    std::vector<Image> tests;
    std::map<std::string, double> sums;
    for (size_t f = 0; f < references.size(); ++f) {
      const Image& reference = references[f];
      tests.push_back(baseline.name == "black image"
                          ? black_baseline(reference)
                          : blurred_baseline(reference, masks[f], baseline_blur_sigma(reference.width(), reference.height())));
      const MetricValues values = compute_metrics(tests.back(), reference, masks[f], per_frame);
      for (const auto& [name, why] : values.undefined)
        if (!score.undefined.count(name)) score.undefined[name] = fmt::format("frame {}: {}", f, why);
      for (const auto& [name, value] : values.values) sums[name] += value;
    }
    for (const std::string& name : per_frame)
      if (!score.undefined.count(name) && sums.count(name) && !references.empty())
        score.values[name] = sums[name] / static_cast<double>(references.size());
    if (flicker) {
      const MetricValue value = temporal_flicker(tests, references, masks);
      if (value.value) score.values["temporal_flicker"] = *value.value;
      else score.undefined["temporal_flicker"] = value.undefined_reason;
    }
    scores.push_back(std::move(score));
  }
  return scores;
}

}  // namespace causticbench
