// Trivial baselines scored like a method (issue 32): the all-black image, which shows no caustic, and the
// reference blurred by a wide Gaussian, which has the caustic's energy where it is but none of its
// sharpness. A method that does not beat the black image on a metric has shown nothing that metric can
// see; a metric on which the black image beats most methods is not ranking caustics. The reports put both
// in every table and as lines on the trade-off plots (docs/metrics.md, "Baselines").
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/image.h"
#include "metrics/metrics.h"

namespace causticbench {

struct Baseline {
  std::string name;         // "black image", "blurred reference"
  std::string description;  // what it is, with its parameters
};

// The baselines in the order reports show them.
const std::vector<Baseline>& baselines();

// The all-black image of the reference's size (3 channels).
Image black_baseline(const Image& reference);

// The reference blurred over the receivers by a Gaussian of `sigma` pixels (a normalised convolution:
// blur(E mask) / blur(mask), so no light leaks in from outside the receivers and none is lost at their
// edges), zero outside the mask.
Image blurred_baseline(const Image& reference, const std::vector<uint8_t>& mask, double sigma);
// The blurred baseline's sigma for an image: 1/32 of its larger side, at least 2 pixels.
double baseline_blur_sigma(int width, int height);

// One baseline's scores on a sequence: per metric, the mean over frames of the per-frame metrics (a
// metric undefined on any frame is undefined), and temporal_flicker over the sequence when it is asked.
struct BaselineScores {
  std::string name;
  std::string detail;  // short, for a table cell: "E_c = 0", "Gaussian, sigma 8 px, over the receivers"
  std::map<std::string, double> values;
  std::map<std::string, std::string> undefined;
};

// Scores every baseline against `references` (frames in order) over `masks` on the metrics `names`.
std::vector<BaselineScores> score_baselines(const std::vector<Image>& references,
                                            const std::vector<std::vector<uint8_t>>& masks,
                                            const std::vector<std::string>& names);

}  // namespace causticbench
