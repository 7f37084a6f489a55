// The reference cache, results/references/<key>/: each scene variant's frames posed once, its reference
// E_c per frame (computed through the lifecycle driver, or loaded from the cache), and what a run record
// says of the reference it was measured against.
//
// A cached frame is used only when its record_NNNN.json passes its schema check and its images match
// the checksums in it; otherwise it is computed again with a warning. Computing takes the reference's
// lock (store/store_lock.h), so that processes sharing a results folder compute each frame once and
// every run is measured against the copy that is stored. A frame whose reference stopped on its time
// cap (max_seconds) is stored with "converged": false and the reason; the runs measured against it say
// so in their records.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/scene.h"
#include "methods/lifecycle.h"
#include "store/result_paths.h"

namespace causticbench {

// One scene variant's reference, as the cache needs to know it.
struct ReferenceRequest {
  const Scene& scene;
  const std::string& reference_key;  // the folder's key: a hash of the scene file, view and settings
  const std::string& content_hash;   // of what the scene's assets hold (a mesh edited in place changes it)
  const ParamSet& params;            // the reference's resolved knobs
  const std::vector<int>& frames;
  std::string label;  // what messages name after "reference <key>": " of variant bunny", or empty
};

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

// Poses the request's frames and loads each cached reference frame, or, under the reference's lock,
// computes it through the lifecycle driver (check_scene included) and stores it; then rewrites the
// reference folder's record.json summary if a frame was computed.
VariantFrames reference_frames(const ReferenceRequest& request, const ResultPaths& paths);

// The checksums of the stored reference images of `frames`, {"frame_0000.exr": {"bytes", "xxhash"}, ...},
// read from their records without loading the images; std::nullopt when a frame is not stored (or its
// record is unreadable). What a run record's "reference_images" is compared with.
std::optional<nlohmann::json> stored_reference_checksums(const ResultPaths& paths, const std::string& reference_key,
                                                         const std::vector<int>& frames);

// True when a stored frame of the variant's reference was computed for other scene content than the
// variant's now (its record's scene_content differs from `content_hash`: a mesh or environment
// map edited in place). variant_frames computes such a frame again; the runs stored against it are due.
bool stored_reference_content_differs(const ResultPaths& paths, const std::string& reference_key,
                                      const std::string& content_hash, const std::vector<int>& frames);

// The fields a run record gets about the reference it was measured against: reference_images (as
// above), reference_converged and, when not converged, reference_unconverged (the first frame's reason).
nlohmann::json reference_fields(const VariantFrames& frames, const std::vector<int>& experiment_frames);

}  // namespace causticbench
