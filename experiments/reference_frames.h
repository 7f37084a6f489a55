// The reference side of an experiment: each variant's reference through the cache (store/reference_cache.h),
// and the check that a reference has caustic light in view before any run starts
// (metrics/caustic_presence.h).
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "experiments/experiment.h"
#include "store/reference_cache.h"
#include "store/result_paths.h"
#include "methods/lifecycle.h"
#include "metrics/caustic_presence.h"

namespace causticbench {

// The variant's frames and reference (store/reference_cache.h) for the experiment's frames.
VariantFrames variant_frames(const Experiment& experiment, const SceneVariant& variant, const ResultPaths& paths);
// Whether a stored frame of the variant's reference was computed for other scene content than the
// variant's now.
bool stored_reference_content_differs(const ResultPaths& paths, const SceneVariant& variant, const std::vector<int>& frames);

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
