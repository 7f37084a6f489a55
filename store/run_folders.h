// A run's folder in the store, runs/<key>/: what it holds (nothing, a record that passes its checks,
// store/record_check.h, or a damaged one) and writing it. Every file goes through core/files.h's atomic
// write helper and the folder through a staging folder (core/staging_folder.h), so a run appears complete
// or not at all, and a sweep killed at any moment resumes with nothing lost and nothing duplicated.
// store/result_store.h answers with these what a run needs. Layout and guarantees: docs/results-format.md.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace causticbench {

// What a run folder holds: nothing, a record that passes its checks, or a damaged one.
struct StoredRun {
  enum class State { absent, stored, damaged };
  State state = State::absent;
  std::string problem;      // damaged: "<folder>/record.json: <what is wrong>"
  nlohmann::json record;    // stored: the record
  std::string record_hash;  // stored: xxHash64 of record.json, which tells whether another process replaced it
};

StoredRun inspect_stored_run(const std::string& run_folder);

// Whether a stored run's record names another reference than its variant's current one (`reference_key`
// of experiment.json's variant): such a run is stale (docs/reports.md, "Stale runs"), `run` measures it
// again and `status` counts it pending. A record that names none (written before variants) is not.
bool measured_against_other_reference(const nlohmann::json& record, const std::string& current_reference_key);
bool run_is_stored(const std::string& run_folder);

// Writes a run folder: its images (file name, EXR bytes) and then its record, which gets their checksums
// under "images", into a staging folder that replaces any copy in place in one atomic step.
void store_run_folder(const std::string& run_folder, const std::vector<std::pair<std::string, std::string>>& images,
                      nlohmann::json record);

}  // namespace causticbench
