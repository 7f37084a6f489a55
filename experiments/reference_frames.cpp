#include "experiments/reference_frames.h"

#include <set>

#include <fmt/format.h>

#include "core/direct_lighting.h"
#include "core/errors.h"

namespace causticbench {

namespace {

// Light samples per pixel and light of the direct irradiance that the empty-reference rule compares E_c
// with: the rule's threshold is a millionth of it, so a rough estimate decides as a converged one would.
constexpr int kPresenceDirectSamples = 4;
constexpr uint64_t kPresenceDirectSeed = 1;


// How much caustic light each frame of the variant's reference has in view (metrics/caustic_presence.h).
std::vector<FramePresence> reference_presence(const Experiment& experiment, const VariantFrames& frames) {
  std::vector<FramePresence> result;
  for (int frame : experiment.frames) {
    const PosedFrame& posed = *frames.posed.at(frame);
    Image direct = direct_irradiance(posed.tracer, posed.gbuffer, kPresenceDirectSamples, kPresenceDirectSeed);
    result.push_back({frame, measure_caustic_presence(frames.reference.at(frame), direct, posed.gbuffer.receiver)});
  }
  return result;
}

std::vector<FramePresence> empty_frames(const std::vector<FramePresence>& presences) {
  std::vector<FramePresence> empty;
  for (const FramePresence& entry : presences)
    if (entry.presence.empty()) empty.push_back(entry);
  return empty;
}

// "frame 0" or "frame 0 (and frames 3, 4)".
std::string frames_text(const std::vector<FramePresence>& frames) {
  std::string text = fmt::format("frame {}", frames.front().frame);
  if (frames.size() == 1) return text;
  std::vector<std::string> others;
  for (size_t i = 1; i < frames.size(); ++i) others.push_back(std::to_string(frames[i].frame));
  return text + fmt::format(" (and frame{} {})", others.size() == 1 ? "" : "s", join(others, ", "));
}

// An empty reference is an input error: the scene, its camera or its lights are not what the experiment
// needs, and every score against it would be undefined or a meaningless perfect value.
[[noreturn]] void throw_empty_reference(const Experiment& experiment, const SceneVariant& variant,
                                        const ResultPaths& paths, const std::vector<FramePresence>& empty) {
  throw InputError(fmt::format(
      "{}: the reference of scene {} (variant {}) has no caustic in view on {}: {}. Every method would be scored "
      "against nothing; {}. No run was started (the reference is kept in {}). An experiment that means to measure "
      "an empty caustic (an extremes case) sets `empty_reference_expected: true`; its runs are then reported as "
      "\"empty reference\", not scored.",
      experiment.source, variant.scene_path, variant.name, frames_text(empty), empty.front().presence.describe(),
      kEmptyCausticHint, paths.reference(variant.reference_key)));
}


}  // namespace

VariantFrames variant_frames(const Experiment& experiment, const SceneVariant& variant, const ResultPaths& paths) {
  const std::string label = experiment.variants.size() > 1 ? " of variant " + variant.name : "";
  return reference_frames(ReferenceRequest{variant.scene, variant.reference_key, variant.content_hash,
                                           experiment.reference_params, experiment.frames, label},
                          paths);
}

bool stored_reference_content_differs(const ResultPaths& paths, const SceneVariant& variant, const std::vector<int>& frames) {
  return stored_reference_content_differs(paths, variant.reference_key, variant.content_hash, frames);
}

ReferenceCheck check_references(const Experiment& experiment, const std::vector<const RunSpec*>& pending,
                                const ResultPaths& paths) {
  std::set<size_t> variants;
  for (const RunSpec* run : pending) variants.insert(run->variant);
  ReferenceCheck check;
  for (size_t index : variants) {
    const SceneVariant& variant = experiment.variants.at(index);
    check.kept_frames = VariantFrames{};  // one variant's frames in memory at a time
    check.kept_frames = variant_frames(experiment, variant, paths);
    check.kept_variant = index;
    std::vector<FramePresence> empty = empty_frames(reference_presence(experiment, check.kept_frames));
    if (empty.empty()) continue;
    if (!experiment.empty_reference_expected) throw_empty_reference(experiment, variant, paths, empty);
    fmt::print(stderr, "reference {} (variant {}) has no caustic in view on {}: its runs are stored as \"empty "
               "reference\", not scored (empty_reference_expected)\n",
               variant.reference_key, variant.name, frames_text(empty));
    check.empty[index] = std::move(empty);
  }
  if (variants.size() > 1) {
    // The runs start with the first variant: keeping the last one's frames would hold two variants at once.
    check.kept_frames = VariantFrames{};
    check.kept_variant.reset();
  }
  if (experiment.empty_reference_expected && check.empty.empty() && !variants.empty()) {
    fmt::print(stderr, "note: empty_reference_expected is set, but every reference checked has a caustic in view; "
               "the runs are scored as usual\n");
  }
  return check;
}


}  // namespace causticbench
