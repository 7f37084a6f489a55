// The size of the ball a method samples an object's caustic in (lpi's volumes, PRT's transfer grid):
// `volume_radius: auto` derives it from where the object's caustic first meets a receiver in the rendered
// frames (caustic_reach.h), and every frame measures the flux that lands outside the ball the run used
// (CausticMethod::lost_flux). Decisions and their reasons: methods/lpi/README.md, "The sampled ball".
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "methods/common/caustic_reach.h"
#include "methods/method.h"

namespace causticbench {

// Probe photons per object and probed frame; at most kProbedFrames frames, spread over those rendered.
inline constexpr uint64_t kProbePhotons = 20000;
inline constexpr size_t kProbedFrames = 8;
// auto: the ball holds this fraction of the probes' first-receiver flux in every probed frame, times the
// margin. Not all of it: a glass object's Fresnel reflections spread a few per cent of its flux thinly
// over every receiver in reach (4.5 % beyond 3 radii on a 6 m floor under a 0.4 m ball), and a grid
// stretched to hold them loses the resolution the focus needs (relMSE 0.006 at 3 radii, 0.025 at 6,
// grid 48). 98 % keeps auto's own loss under the 5 % at which a run is warned about.
inline constexpr double kHeldFraction = 0.98;
inline constexpr double kRadiusMargin = 1.1;

struct BallRadius {
  double radii = 3.0;   // the ball's radius used, in bounding radii
  double needed = 0.0;  // auto: what the caustic asked for before the cap (0: a number was set)
  bool capped = false;
  double lost_at_cap = 0.0;  // capped: the largest fraction over the probed frames beyond the cap
  std::string reason;   // for the run record
};

// The largest ball auto chooses for samples `cells_across` cells (or shells) across the ball's diameter:
// one whose cells still resolve the object, at least 8 across its bounding ball; never below 3, the old
// default.
double ball_radius_cap(double cells_across);

// The ball for `object` (a scene index; `build_bounds` its bounding sphere in build space): `requested`
// bounding radii when it is positive, or with auto (0) what the probes over context's frames need, capped
// at ball_radius_cap(cells_across).
BallRadius choose_ball_radius(const PrepareContext& context, int object, const BoundingSphere& build_bounds,
                              double requested, double cells_across);

// The probes of one frame (kProbePhotons, a fixed seed), measured from `build_bounds`' centre.
CausticReach frame_reach(const SceneFrame& frame, const Tracer& tracer, int object, const BoundingSphere& build_bounds);

// The probes of each of at most kProbedFrames of context's frames, evenly spread, first and last included
// (frames whose probes meet no receiver give an empty reach).
std::vector<CausticReach> probe_frames(const PrepareContext& context, int object, const BoundingSphere& build_bounds);

// A frame's caustic flux against the balls of its objects, summed over objects (each add() probes one):
// the flux that first meets a receiver, the part of it beyond the object's ball, and the largest ball
// (in bounding radii) that auto would choose for this frame, and of the flux inside the balls, what
// lpi's paper orientation renders (CausticReach::paper_flux_within). What lost_flux reports.
struct BallLoss {
  double total = 0.0, beyond = 0.0, needed = 0.0, paper_inside = 0.0;
  void add(const SceneFrame& frame, const Tracer& tracer, int object, const BoundingSphere& build_bounds, double radii);
  double fraction() const { return total > 0.0 ? beyond / total : 0.0; }
  // The light inside the balls that the paper orientation does not render, net of what it renders in
  // excess, as a fraction of the total (0 where it renders all of it or more).
  double paper_orientation_loss() const {
    return total > 0.0 ? std::max(0.0, (total - beyond - paper_inside) / total) : 0.0;
  }
};

}  // namespace causticbench
