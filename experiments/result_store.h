// Where results live and how they are written and read back. Every file goes through core/files.h's
// atomic write helper and every run folder through a staging folder (core/staging_folder.h), so a run
// or a reference frame appears complete or not at all, and a sweep killed at any moment resumes with
// nothing lost and nothing duplicated. Every stored record is checked when read
// (experiments/record_check.h); processes that share a results folder take a lock per reference and
// per run (experiments/store_lock.h). Layout and guarantees: docs/results-format.md.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/staging_folder.h"

namespace causticbench {

// --results names a folder this process can write, or one it can create: checked before any work, so
// that a file of that name, a symbolic-link loop or a read-only parent is an input error (exit code 2)
// naming the path and the system's reason, not an internal error after the reference was computed.
void check_results_folder(const std::string& path);
// The same check for any folder an option names (`option` and `what` in the message): a writable folder, or
// one that can be made below a writable one; InputError (exit 2) otherwise.
void check_writable_folder(const std::string& option, const std::string& what, const std::string& path);

struct ResultPaths {
  std::string results;  // the results root, e.g. "results"

  std::string experiment(const std::string& name) const;
  std::string run(const std::string& experiment_name, const std::string& key) const;
  std::string reference(const std::string& key) const;
  std::string builds() const;  // the build cache: <results>/builds/<key>/ (methods/build_cache.h)
  // Lock files: <results>/.locks/references/<key>.lock and <results>/.locks/runs/<experiment>/<key>.lock
  // (a hidden folder, which no experiment name can be).
  std::string reference_lock(const std::string& key) const;
  std::string run_lock(const std::string& experiment_name, const std::string& key) const;
  static std::string frame_file(int frame, const std::string& prefix = "frame");
};

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
