// lpi's `orientation: auto` (issue 52): the paper's orientation where the scene's receivers face the
// objects' centres closely enough for its cosine to keep the light, the vector irradiance elsewhere.
// Decisions and their reasons: methods/lpi/README.md, "Orientation".
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "methods/common/ball_radius.h"
#include "methods/lpi/precompute.h"
#include "methods/method.h"

namespace causticbench::lpi {

// auto keeps the paper orientation while its cosine renders the probes' light within this fraction of
// what lands, in every probed frame: what the lost-flux warning (5 %) leaves beside the 2 % that
// `volume_radius: auto` lets land outside its ball, so that auto's two choices together stay under the
// warning. Shipped scenes (`causticbench render` of each scene of configs/scenes/ with -m lpi, the
// record's orientation_why): ring 0.169, cup 0.44, water pool 0.22, glass cube 0.62, glass sphere 1.10 (light
// converging to the focus crosses the floor obliquely), bunny 0.971.
inline constexpr double kPaperOrientationTolerance = kLostFluxWarning - (1.0 - kHeldFraction);

struct OrientationChoice {
  Orientation orientation = Orientation::paper;
  // Over the probed frames, the lowest and highest share of the probes' light the paper orientation
  // renders (1 and 1 where no probe met a receiver).
  double lowest_share = 1.0, highest_share = 1.0;
  std::string reason;  // for the run record
};

// `objects`: the specular objects' scene indices with their bounding spheres in build space. With
// `one_cell` (grid_resolution 1 or multires_depth 0) the paper orientation has no direction from the
// centre to read: vector.
OrientationChoice choose_orientation(const PrepareContext& context,
                                     const std::vector<std::pair<int, BoundingSphere>>& objects, bool one_cell);

}  // namespace causticbench::lpi
