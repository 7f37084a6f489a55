// Image and temporal error metrics of a method's caustic irradiance E_c against the reference, over the
// receiver mask, and the registry that names them and says which direction is better.
// Exact definitions: docs/metrics.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"

namespace causticbench {

struct MetricInfo {
  std::string name;              // "mse", "rmse", "psnr", "ssim", "relmse", "energy_ratio", "max_error", "flip",
                                 // "temporal_flicker", "nonfinite_pixels"
  bool higher_is_better = false;  // meaningful only when target is empty
  std::optional<double> target;  // the ideal value when best means "closest to it" (energy_ratio: 1)
  std::string unit;              // "(W/m^2)^2", "W/m^2", "dB", "" (dimensionless), "pixels"
  std::string definition;        // one line
  bool per_frame = true;         // false only for temporal_flicker (needs a sequence)
  // What a value can be (the record check refuses a stored value outside, or an infinite one): ssim in
  // [-1, 1], flip in [0, 1], the others within what images of float values can give (metrics.cpp derives
  // each bound; psnr's +inf, for mse 0, is stored as undefined).
  double minimum = 0.0;
  double maximum = std::numeric_limits<double>::infinity();
};

// Every metric, in a fixed order (the order reports list them in).
const std::vector<MetricInfo>& metric_registry();
// The registered metric of that name, or null.
const MetricInfo* metric_info(const std::string& name);
// Throws InputError naming the closest known metric for unknown names.
const MetricInfo& find_metric(const std::string& name);
// True if value a is strictly better than b for this metric: closer to the target when the metric has
// one, otherwise larger (higher_is_better) or smaller. NaN is never better than anything, and any
// non-NaN value is better than NaN.
bool metric_better(const MetricInfo& metric, double a, double b);

// A metric's value, or why it has none. A metric normalised by a quantity of the reference (PSNR's peak,
// SSIM's dynamic range, relMSE's mean, the energy ratio's flux, flicker's mean) is undefined when that
// quantity is 0: a reference with no caustic in view gives no scale, and 0/0 must never read as a
// perfect score. Which metric is undefined when: docs/metrics.md, "Undefined values".
struct MetricValue {
  std::optional<double> value;
  std::string undefined_reason;  // set exactly when value is empty
};

struct MetricValues {
  std::map<std::string, double> values;          // the defined metrics, always with nonfinite_pixels
  std::map<std::string, std::string> undefined;  // metric name -> why it has no value
  size_t nonfinite_pixels = 0;  // masked test pixels with a NaN or infinite channel
  // The settings a defined value depends on, for the metrics that have any, to store beside the value:
  // "flip" -> pixels_per_degree, start_exposure, stop_exposure, exposures (HDR-FLIP with ACES).
  std::map<std::string, std::map<std::string, double>> parameters;
};

// Computes the named per-frame metrics of `test` against `reference` over `mask` (one byte per pixel,
// non-zero = counts). Only the first three channels (RGB) are used. Non-finite test pixels are counted
// in nonfinite_pixels (always also stored as values["nonfinite_pixels"]) and EXCLUDED from every other
// metric, exactly as if they were outside the mask; flip, which filters the image, first sets them to 0 in
// the test image (so NaN cannot spread), then leaves them out of its mean (metrics/flip.h, caustic_flip()).
// Each requested name lands in exactly one of `values` and `undefined`; if no masked pixel is finite, every
// other metric is undefined. Throws
// InputError for an unknown or non-per-frame name (temporal_flicker), and std::invalid_argument for
// mismatched sizes or a non-finite reference value inside the mask.
MetricValues compute_metrics(const Image& test, const Image& reference, const std::vector<uint8_t>& mask,
                             const std::vector<std::string>& names);

// Temporal flicker of an animation: mean over frames t>=1 of the masked mean absolute value of
// (test_t - test_{t-1}) - (reference_t - reference_{t-1}) (all three channels), over pixels masked in both
// frames and finite in both test frames, divided by the masked mean of the reference over all frames
// (so it is scale free). Zero when the method's frame-to-frame change equals the reference's. Undefined
// with fewer than two frames, when no frame pair shares a finite masked pixel, or when the reference's
// mean is 0.
MetricValue temporal_flicker(const std::vector<Image>& test, const std::vector<Image>& reference,
                             const std::vector<std::vector<uint8_t>>& masks);

}  // namespace causticbench
