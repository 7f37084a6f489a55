// Where a run's light went (issue 52): against the reference's caustic light in view, a run's measured
// energy ratio, the method's own lost flux (what its knobs can recover: methods/method.h, LostFlux), its
// model share (the reference's light in the path classes it declares it does not model: the joint
// interaction x light shares of the reference's `path_classes`, core/path_classes.h) and what is left.
// The declarations and the lost flux account for an energy between
//   lowest = 1 - min(1, lost + model)   (none of the unmodelled light delivered; lost and model may name the
//                                        same light, so together they explain at most all of it) and
//   highest = 1 - (lost - moved) + excess
//                                       (the lost flux's moved part may still land in view: LostFlux::moved;
//                                        a method that does not model a class may still put out an
//                                        approximation of its light: csl's cones on a mirror ring; and a
//                                        method that does not model occlusion may add the light occluders
//                                        block, `excess`, the reference's occlusion "excess"; without
//                                        bound where more than the tolerance of the light is of a kind
//                                        the method does not model: it runs such a scene with a light it
//                                        models in its place, pinhole's, lpi's and prt's distant light for
//                                        a point light, whose energy is that light's: 3.4 times the
//                                        reference's on the point-light case),
// and unexplained is the energy's distance outside that interval, signed: lowest - energy when below (light
// missing), highest - energy when above (light in excess), 0 within.
// A run whose unexplained part is beyond kUnexplainedLightTolerance is flagged. The tolerance is the
// capability verdict's energy tolerance (experiments/capability_verdict.h, 0.15): the largest energy error
// a method may show on a case it declares it models; the reference's own share errors are far below it
// (hundredths of a percent at the shipped settings). One definition for the runner's warning
// (experiments/runner.cpp) and the report, which accounts each run once as it loads (Run::light_account).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/capability_verdict.h"
#include "methods/method.h"
#include "store/run_record.h"

namespace causticbench {

inline constexpr double kUnexplainedLightTolerance = kCapabilityEnergyTolerance;

struct LightAccount {
  double energy = 0.0, lost = 0.0, model = 0.0, unexplained = 0.0;
  double moved = 0.0;  // of `lost`, the light moved rather than dropped (LostFlux::moved)
  // The light occluders block in view, as a fraction of the reference's, where the method declares that it
  // does not model occlusion (0 otherwise): what it may put out beyond the reference.
  double excess = 0.0;
  // The share of the reference's light in view of a light kind the method does not model (part of `model`):
  // beyond kUnexplainedLightTolerance its energy is bounded below only (the substitute light's energy).
  double substituted = 0.0;
  // The capabilities the method lacks that the scene's light needs, each with the share of the reference's
  // light in view that needs it (a path may need two), largest first.
  std::vector<std::pair<std::string, double>> unmodelled;
  bool flagged = false;
};

// The reference record's in-view split ("path_classes" "in_view") where it holds light in view: its
// "pixel_sum" (the image's summed E_c the split weights by) or, computed before that weighting, its
// "flux", above 0; nullptr otherwise (computed before issue 52, or nothing in view).
const nlohmann::json* reference_light_in_view(const nlohmann::json& reference_record);

// The account, or nothing when the reference record has no joint split (computed before issue 52) or no
// caustic light in view.
// `moved`: the part of `lost_fraction` the method moved rather than dropped (LostFlux::moved).
std::optional<LightAccount> account_for_light(const nlohmann::json& reference_record, const Capabilities& capabilities,
                                              double energy_ratio, double lost_fraction, double moved = 0.0);

// The account of a stored run against its reference's record.json: the method as this build registers it,
// the energy ratio measured, the lost flux as the mean over the frames that report one. Nothing when the run
// measured no energy ratio or this build does not register its method (its declarations are unknown here).
std::optional<LightAccount> account_for_record(const nlohmann::json& reference_record, const RunRecord& run);

// The account of each of the run's frames that has an energy ratio, against the reference's split of that
// frame (its record.json "frames"; the top-level split for a reference of one frame) and that frame's lost
// flux: what the mean account (account_for_record) hides in an animation, a frame whose light went missing.
struct FrameLightAccount {
  int frame = 0;
  LightAccount account;
};
std::vector<FrameLightAccount> frame_accounts(const nlohmann::json& reference_record, const RunRecord& run);

// "multiple_bounces 31.0 %, point_light 1.0 %": the capabilities the method lacks, with their shares.
std::string unmodelled_text(const LightAccount& account);

// "does not model 31.0 % of this scene's caustic in view (multiple_bounces 31.0 %)", "may add up to 23.0 %
// that occluders block (occlusion)" and, when flagged,
// "unexplained: 0.58 of the light missing, not a declared limit" (or "... in excess ...").
std::string describe_light_account(const LightAccount& account);

}  // namespace causticbench
