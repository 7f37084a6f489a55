#include "methods/lpi/orientation_choice.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "methods/common/ball_radius.h"

namespace causticbench::lpi {

OrientationChoice choose_orientation(const PrepareContext& context,
                                     const std::vector<std::pair<int, BoundingSphere>>& objects, bool one_cell) {
  OrientationChoice choice;
  if (one_cell) {
    choice.orientation = Orientation::vector;
    choice.reason = "orientation: auto; one cell has no direction from the centre for the paper's cosine: vector";
    return choice;
  }
  // Per probed frame (the same frames for every object), the objects' light summed: what lands and what
  // the paper orientation renders of it.
  std::vector<double> landed, rendered;
  for (const auto& [object, bounds] : objects) {
    const std::vector<CausticReach> reaches = probe_frames(context, object, bounds);
    landed.resize(std::max(landed.size(), reaches.size()), 0.0);
    rendered.resize(landed.size(), 0.0);
    for (size_t frame = 0; frame < reaches.size(); ++frame) {
      landed[frame] += reaches[frame].total_flux;
      rendered[frame] += reaches[frame].paper_flux_within(INFINITY);
    }
  }
  size_t lit = 0;  // probed frames in which some probe met a receiver
  for (size_t frame = 0; frame < landed.size(); ++frame) {
    if (!(landed[frame] > 0.0)) continue;
    const double share = rendered[frame] / landed[frame];
    choice.lowest_share = lit > 0 ? std::min(choice.lowest_share, share) : share;
    choice.highest_share = lit > 0 ? std::max(choice.highest_share, share) : share;
    ++lit;
  }
  if (lit == 0) {
    choice.reason = fmt::format("orientation: auto; no probe photon met a receiver after an object in the {} probed "
                                "frame(s): paper",
                                landed.size());
    return choice;
  }
  const bool keeps = choice.lowest_share >= 1.0 - kPaperOrientationTolerance &&
                     choice.highest_share <= 1.0 + kPaperOrientationTolerance;
  choice.orientation = keeps ? Orientation::paper : Orientation::vector;
  choice.reason = fmt::format(
      "orientation: auto; the paper's cosine renders {} of the light {} probe photons per object and frame land on "
      "the receivers ({} frame(s)), {} 1 +- {:.2g}: {}",
      choice.lowest_share == choice.highest_share
          ? fmt::format("{:.3f}", choice.lowest_share)
          : fmt::format("{:.3f} to {:.3f}", choice.lowest_share, choice.highest_share),
      kProbePhotons, lit, keeps ? "within" : "outside", kPaperOrientationTolerance,
      keeps ? "paper" : "vector");
  return choice;
}

}  // namespace causticbench::lpi
