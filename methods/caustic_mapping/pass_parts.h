// The steps of a caustics-mapping pass (light_pass.h), one file each: the receiver map and the receiver
// search (receiver_search.cpp), the splats (splat.cpp).
#pragma once

#include <vector>

#include "methods/caustic_mapping/light_pass.h"

namespace causticbench::caustic_mapping {

// The receiver map over `view`'s window at resolution^2, its rays starting `back` behind the window
// (orthographic) or at the light (perspective), looking through `object` (the pass's own).
ReceiverMap render_receiver_map(const Tracer& tracer, const LightView& view, int resolution, double back,
                                int object = -1);

enum class SearchFailure { none, left_view, no_receiver, not_converged };

struct SearchResult {
  SearchFailure failure = SearchFailure::none;
  Vec3 hit{0.0f};
  int steps = 0;  // receiver-map reads
};

// Where the ray from `origin` along `direction` (unit) meets the receivers: the paper's image-space
// search over the receiver map (start at the receiver behind the origin's own texel, then
// `iterations` times: project origin + d direction, read the receiver there, d = its distance), or with
// `exact` a real ray through the tracer. The image-space estimate counts as converged when the receiver
// it ends on lies on the ray to within what a texel of the map spans on that receiver; with `refine` the
// hit is where the ray meets that receiver's plane rather than the receiver itself (hit_position: plane).
SearchResult search_receiver(const ReceiverMap& map, const Tracer& tracer, const Vec3& origin, const Vec3& direction,
                             int iterations, bool exact, bool refine = false);

// A photon that found its receiver: where in the caustic map (continuous texel coordinates: texel (x, y)
// spans [x, x + 1) x [y, y + 1)) and its flux.
struct LandedPhoton {
  float x = 0, y = 0;
  Color flux{0.0f};
};

// Splats the photons into an n x n RGB flux map (3 n^2 doubles, zeroed first) with the settings' kernel,
// each photon's weights normalised to 1 over the texels inside the map, so that every photon's flux lands
// whole. Deterministic for any thread count (each row band adds the photons that touch it by their
// first row, then in photon order).
void splat_photons(const std::vector<LandedPhoton>& photons, const Settings& settings, int n, std::vector<double>& flux);

}  // namespace causticbench::caustic_mapping
