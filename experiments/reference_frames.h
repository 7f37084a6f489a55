// The reference side of a run: each variant's frames posed once, its reference E_c per frame (computed
// through the lifecycle driver and cached in results/references/<key>/, or loaded from there), and the
// check that a reference has caustic light in view before any run starts (metrics/caustic_presence.h).
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "experiments/experiment.h"
#include "experiments/result_store.h"
#include "methods/lifecycle.h"
#include "metrics/caustic_presence.h"

namespace causticbench {

// The frames of one scene variant, posed once and shared by its reference and all its runs (methods
// take them by const reference), with the reference's E_c of each.
struct VariantFrames {
  std::map<int, std::unique_ptr<PosedFrame>> posed;
  std::map<int, Image> reference;
  std::vector<const PosedFrame*> sequence(const std::vector<int>& frames) const {
    std::vector<const PosedFrame*> result;
    for (int frame : frames) result.push_back(posed.at(frame).get());
    return result;
  }
};

// Poses the variant's frames and loads each cached reference frame, or computes it through the
// lifecycle driver (check_scene included) and stores it; then rewrites the reference folder's
// record.json summary if a frame was computed.
VariantFrames variant_frames(const Experiment& experiment, const SceneVariant& variant, const ResultPaths& paths);

struct FramePresence {
  int frame = 0;
  CausticPresence presence;
};

// The reference of every variant with runs to do, checked before the first run: the empty frames of each
// variant (only when the experiment expects them; otherwise the first empty one is an InputError), and,
// when only one variant has runs to do, its frames, so that it poses them once.
struct ReferenceCheck {
  std::map<size_t, std::vector<FramePresence>> empty;  // variant -> its frames without caustic in view
  std::optional<size_t> kept_variant;
  VariantFrames kept_frames;
};

// Computes or loads the reference of every variant with pending runs; an empty one is an InputError
// naming the scene, the variant, the frames and what to check, unless the experiment expects it.
ReferenceCheck check_references(const Experiment& experiment, const std::vector<const RunSpec*>& pending,
                                const ResultPaths& paths);

}  // namespace causticbench
