// FLIP, NVIDIA's perceptual image-difference evaluator: LDR-FLIP (Andersson et al., HPG 2020) and
// HDR-FLIP (Andersson et al., EG 2021), exactly as ../shared/metrics/flip.md specifies them (which matches
// the reference implementation v1.6), in 32-bit floats with clamp-to-edge separable convolutions.
// The project's metric on E_c (`flip` in metrics/metrics.h) is caustic_flip() below: HDR-FLIP with the
// exposure range taken over the receiver mask, because flip.md's automatic range breaks on caustic images
// (section 10). docs/metrics.md, "flip", has the definition.
//
// Argument order: the FLIP functions take (reference, test), like the papers and the reference tool; the
// project-level caustic_flip() and flip_error_map() take (test, reference), like compute_metrics().
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"

namespace causticbench {

// 0.7 m from a 0.7 m wide 3840-pixel display: 3840 * pi / 180.
inline constexpr float kFlipDefaultPixelsPerDegree = 67.0206432f;

// The caustic exposure rule's "lit" threshold: receiver pixels whose reference luminance is above this
// fraction of the brightest one give the stop exposure. 2^-10 keeps the range within 10 stops of the
// peak (N <= 10), below which a caustic's photon-noise floor would decide the exposure.
inline constexpr double kFlipLitFraction = 1.0 / 1024.0;

enum class FlipToneMapper { aces, hable, reinhard };

struct FlipOptions {
  float pixels_per_degree = kFlipDefaultPixelsPerDegree;
  // HDR only. Unset bounds come from the reference (flip.md section 6); a set start must not exceed stop.
  FlipToneMapper tone_mapper = FlipToneMapper::aces;
  std::optional<float> start_exposure, stop_exposure;
  std::optional<int> exposures;  // N; default max(2, ceil(stop - start))
};

struct FlipExposureRange {
  float start = 0.0f, stop = 0.0f;
  int count = 0;  // N
};

struct HdrFlipResult {
  Image error_map;     // W x H, 1 channel, in [0, 1]
  Image exposure_map;  // W x H, 1 channel: i / (N - 1) of the first exposure giving the pixel's maximum
  FlipExposureRange exposures;
};

// Pooled statistics of an error map (flip.md section 7). The mean is the headline value.
struct FlipPooled {
  double mean = 0.0, weighted_median = 0.0, first_weighted_quartile = 0.0, third_weighted_quartile = 0.0;
  double min = 0.0, max = 0.0;
  size_t pixels = 0;
};

// LDR-FLIP of two linear-RGB images (first 3 channels; clamped to [0, 1] first). Returns the W x H
// single-channel error map. Throws std::invalid_argument for mismatched sizes or fewer than 3 channels.
Image flip_error_map_ldr(const Image& reference, const Image& test, const FlipOptions& options = {});

// HDR-FLIP of two linear scene-referred images (first 3 channels, >= 0, not clamped). The unset exposure
// bounds come from the whole reference, exactly as the reference tool does; a bound that is not finite
// (a median luminance of 0, see flip.md section 10) throws std::invalid_argument instead of overflowing N.
HdrFlipResult flip_error_map_hdr(const Image& reference, const Image& test, const FlipOptions& options = {});

// flip.md section 6's automatic range over the whole reference (start from the maximum luminance, stop
// from the upper median), with the user's bounds from `options` kept. Not finite when the max or median is 0.
FlipExposureRange flip_exposure_range(const Image& reference, const FlipOptions& options = {});

// Mean, weighted median and quartiles, min and max of a 1-channel map over `mask` (empty: every pixel).
FlipPooled flip_pool(const Image& error_map, const std::vector<uint8_t>& mask = {});
// flip.md's value-weighted percentile: the first sorted value whose running sum exceeds p * total (0 when
// every value is 0).
double flip_weighted_percentile(std::vector<float> values, double p);

// The project's FLIP on caustic irradiance E_c.
//   * Pixels outside `mask` are set to 0 in both images before filtering, so nothing outside the receivers
//     changes the value; a masked test pixel with a NaN or infinite channel is set to 0 (so NaN never
//     spreads through the filters) and left out of the mean. Negative values are set to 0 (E_c >= 0; the
//     tone curves are not meant for x < 0, ACES maps a large negative value to white).
//   * Exposures from the reference's masked pixels: start = log2(xmax / Ymax), stop = log2(xmax / Ymedian)
//     with Ymedian the upper median of the masked pixels whose luminance exceeds kFlipLitFraction * Ymax.
//     The lit set holds the brightest pixel, so stop is finite and >= start whenever Ymax > 0.
//   * Undefined (undefined_reason set, no map) when the reference's masked maximum luminance is 0 or no
//     masked test pixel is finite. Throws std::invalid_argument for mismatched sizes or mask, fewer than 3
//     channels, or a non-finite reference value inside the mask.
struct CausticFlip {
  Image error_map;   // W x H, 1 channel, 0 outside the mask; empty when undefined
  FlipExposureRange exposures;
  double mean = 0.0;       // over masked pixels with a finite test value
  size_t pixels = 0;       // how many that is
  std::string undefined_reason;
  bool defined() const { return undefined_reason.empty(); }
};
CausticFlip caustic_flip(const Image& test, const Image& reference, const std::vector<uint8_t>& mask,
                         const FlipOptions& options = {});
// caustic_flip()'s error map, for the report's image grid (empty when the value is undefined).
Image flip_error_map(const Image& test, const Image& reference, const std::vector<uint8_t>& mask);

// Building blocks, exposed for the tests.
float flip_srgb_to_linear(float encoded);                   // one channel, encoded in [0, 1]
int flip_spatial_radius(float pixels_per_degree);          // rs, 10 at the default ppd
int flip_feature_radius(float pixels_per_degree);          // rf, 9 at the default ppd
float flip_cmax();                                         // 41.2761
float flip_tone_mapper_xmax(FlipToneMapper tone_mapper);   // input reaching 0.85; ACES 2.118872
// Linear RGB to YCxCz (3 channels), and the CSF filter of a YCxCz image (flip.md section 3, step 2).
Image flip_linear_rgb_to_ycxcz(const Image& linear_rgb);
Image flip_csf_filter(const Image& ycxcz, float pixels_per_degree);

}  // namespace causticbench
