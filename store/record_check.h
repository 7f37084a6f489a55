// The checks a stored record passes before the store counts it as stored (docs/results-format.md,
// "Guarantees"): a schema check (the required fields, each of its type) and the checksums of the images
// it names. A record that fails them is not stored: `causticbench run` computes it again with a
// warning that names the file and what is wrong, and the report shows it as failed, never as ok.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace causticbench {

// Why a run's record.json, parsed, cannot be used ("" when it can): it reads as a RunRecord
// (store/run_record.h: every field of its type, a version this build knows), its key is the
// folder's name, and every image an ok one names is in `run_folder`, matching its checksum under
// "images" (records written before checksums carry none and are checked for presence only).
std::string run_record_problem(const nlohmann::json& record, const std::string& run_folder);

// Why a reference frame's record_NNNN.json, parsed, cannot be used ("" when it can): frame (== `frame`),
// passes, seconds, reference_error, stop_reason; image and gbuffer checksums are checked by the caller
// against the files (experiments/reference_frames.h).
std::string reference_frame_record_problem(const nlohmann::json& record, int frame);

// std::nullopt when the reference frame's image is a function of its settings alone (it stopped on its
// reference error or its pass count), otherwise why not (it stopped on its time cap, max_seconds).
std::optional<std::string> reference_unconverged_reason(const nlohmann::json& frame_record);

}  // namespace causticbench
