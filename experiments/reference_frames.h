// The reference side of a run: each variant's frames posed once, its reference E_c per frame (computed
// through the lifecycle driver and cached in results/references/<key>/, or loaded from there), and the
// check that a reference has caustic light in view before any run starts (metrics/caustic_presence.h).
//
// A cached frame is used only when its record_NNNN.json passes its schema check and its images match
// the checksums in it; otherwise it is computed again with a warning. Computing takes the reference's
// lock (experiments/store_lock.h), so that processes sharing a results folder compute each frame once
// and every run is measured against the copy that is stored. A frame whose reference stopped on its time
// cap (max_seconds) is stored with "converged": false and the reason; the runs measured against it say
// so in their records.
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
  std::map<int, nlohmann::json> reference_checksums;  // frame -> content_checksum() of its stored EXR
  std::map<int, std::string> unconverged;             // frame -> why its reference is not converged
  std::vector<const PosedFrame*> sequence(const std::vector<int>& frames) const {
    std::vector<const PosedFrame*> result;
    for (int frame : frames) result.push_back(posed.at(frame).get());
    return result;
  }
};

// Poses the variant's frames and loads each cached reference frame, or, under the reference's lock,
// computes it through the lifecycle driver (check_scene included) and stores it; then rewrites the
// reference folder's record.json summary if a frame was computed.
VariantFrames variant_frames(const Experiment& experiment, const SceneVariant& variant, const ResultPaths& paths);

// The checksums of the stored reference images of `frames`, {"frame_0000.exr": {"bytes", "xxhash"}, ...},
// read from their records without loading the images; std::nullopt when a frame is not stored (or its
// record is unreadable). What a run record's "reference_images" is compared with.
std::optional<nlohmann::json> stored_reference_checksums(const ResultPaths& paths, const std::string& reference_key,
                                                         const std::vector<int>& frames);

// True when a stored frame of the variant's reference was computed for other scene content than the
// variant's now (its record's scene_content differs from SceneVariant::content_hash: a mesh or environment
// map edited in place). variant_frames computes such a frame again; the runs stored against it are due.
bool stored_reference_content_differs(const ResultPaths& paths, const SceneVariant& variant, const std::vector<int>& frames);

// The fields a run record gets about the reference it was measured against: reference_images (as
// above), reference_converged and, when not converged, reference_unconverged (the first frame's reason).
nlohmann::json reference_fields(const VariantFrames& frames, const std::vector<int>& experiment_frames);

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
