#include "methods/common/ball_radius.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <fmt/format.h>

namespace causticbench {

namespace {

// The probes' seed: fixed, so that auto chooses the same ball in every process (the build's key holds it).
constexpr uint64_t kProbeSeed = 0x5eedba11;

// At most kProbedFrames of `frames`, evenly spread, first and last included.
std::vector<int> probed_frames(const std::vector<int>& frames) {
  if (frames.size() <= kProbedFrames) return frames;
  std::vector<int> chosen;
  for (size_t k = 0; k < kProbedFrames; ++k)
    chosen.push_back(frames[k * (frames.size() - 1) / (kProbedFrames - 1)]);
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  return chosen;
}

}  // namespace

double ball_radius_cap(double cells_across) {
  // The object's bounding ball (2 radii across) spans at least 8 of the 2R / cells wide cells.
  return std::max(3.0, cells_across / 8.0);
}

CausticReach frame_reach(const SceneFrame& frame, const Tracer& tracer, int object, const BoundingSphere& build_bounds) {
  const BuildSpaceMap map = build_space_map(frame.scene->objects[object], frame.frame);
  return probe_caustic_reach(frame, tracer, object, map, build_bounds, kProbePhotons, kProbeSeed);
}

std::vector<CausticReach> probe_frames(const PrepareContext& context, int object, const BoundingSphere& build_bounds) {
  std::vector<CausticReach> reaches;
  for (int index : probed_frames(context.frames)) {
    if (index == static_cast<int>(context.rest.frame)) {
      reaches.push_back(frame_reach(context.rest, context.tracer, object, build_bounds));
      continue;
    }
    const SceneFrame posed(context.scene, index);
    const Tracer tracer(posed);
    reaches.push_back(frame_reach(posed, tracer, object, build_bounds));
  }
  return reaches;
}

BallRadius choose_ball_radius(const PrepareContext& context, int object, const BoundingSphere& build_bounds,
                              double requested, double cells_across) {
  BallRadius chosen;
  if (requested > 0.0) {
    chosen.radii = requested;
    chosen.reason = fmt::format("volume_radius: {} (set)", requested);
    return chosen;
  }
  double needed = 0.0;
  int frames_with_caustic = 0;
  std::vector<CausticReach> reaches;
  for (CausticReach& reach : probe_frames(context, object, build_bounds)) {
    if (!(reach.total_flux > 0.0)) continue;
    ++frames_with_caustic;
    needed = std::max(needed, reach.radius_holding(kHeldFraction));
    reaches.push_back(std::move(reach));
  }
  const double cap = ball_radius_cap(cells_across);
  if (frames_with_caustic == 0) {
    chosen.radii = 3.0;
    chosen.reason = fmt::format("volume_radius: auto; no probe photon of the {} probed frame(s) met a receiver after "
                                "the object: the old default of 3 bounding radii",
                                probed_frames(context.frames).size());
    return chosen;
  }
  chosen.needed = needed * kRadiusMargin;
  // Never inside the object's own bounding ball: its caustic inside glass is part of what lpi stores.
  chosen.radii = std::max(1.0 * kRadiusMargin, chosen.needed);
  if (chosen.radii > cap) {
    chosen.capped = true;
    chosen.radii = cap;
    for (const CausticReach& reach : reaches) chosen.lost_at_cap = std::max(chosen.lost_at_cap, reach.fraction_beyond(cap));
  }
  chosen.reason = fmt::format(
      "volume_radius: auto; {:.0f} % of the caustic flux of {} probe photons per frame ({} frame(s)) first meets a "
      "receiver within {:.3g} bounding radii, times {} margin: {:.3g}{}",
      100.0 * kHeldFraction, kProbePhotons, frames_with_caustic, needed, kRadiusMargin, chosen.needed,
      chosen.capped ? fmt::format(", capped at {:.3g}, the largest ball this storage resolves (8 cells across the "
                                  "object); {:.1f} % of the caustic lands beyond it (lost_flux)",
                                  cap, 100.0 * chosen.lost_at_cap)
                    : "");
  return chosen;
}

void BallLoss::add(const SceneFrame& frame, const Tracer& tracer, int object, const BoundingSphere& build_bounds,
                   double radii) {
  const CausticReach reach = frame_reach(frame, tracer, object, build_bounds);
  total += reach.total_flux;
  beyond += reach.fraction_beyond(radii) * reach.total_flux;
  paper_inside += reach.paper_flux_within(radii);
  needed = std::max(needed, reach.radius_holding(kHeldFraction) * kRadiusMargin);
}

}  // namespace causticbench
