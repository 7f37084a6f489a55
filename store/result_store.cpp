#include "store/result_store.h"

#include <fmt/format.h>

#include "store/reference_cache.h"
#include "store/run_record.h"

namespace causticbench {


ResultStore::ResultStore(ResultPaths paths, std::string experiment, std::vector<int> frames)
    : paths_(std::move(paths)), experiment_(std::move(experiment)), frames_(std::move(frames)) {}

const std::optional<nlohmann::json>& ResultStore::reference_checksums(const std::string& reference_key) {
  auto it = checksums_.find(reference_key);
  if (it == checksums_.end())
    it = checksums_.emplace(reference_key, stored_reference_checksums(paths_, reference_key, frames_)).first;
  return it->second;
}

bool ResultStore::reference_content_differs(const RunAddress& run) {
  const std::string key = run.reference_key + "/" + run.content_hash;
  auto it = content_differs_.find(key);
  if (it == content_differs_.end())
    it = content_differs_.emplace(key, stored_reference_content_differs(paths_, run.reference_key, run.content_hash, frames_))
             .first;
  return it->second;
}

void ResultStore::references_changed() {
  checksums_.clear();
  content_differs_.clear();
}

RunState ResultStore::look_up(const RunAddress& run, bool warn) {
  StoredRun stored = inspect_stored_run(paths_.run(experiment_, run.key));
  RunState state;
  if (stored.state == StoredRun::State::absent) return state;
  if (stored.state == StoredRun::State::damaged) {
    state.kind = RunState::Kind::damaged;
    state.problem = stored.problem;
    if (warn) fmt::print(stderr, "warning: {}; the run is not counted as stored and is measured again\n", stored.problem);
    return state;
  }
  state.record = std::move(stored.record);
  state.record_hash = std::move(stored.record_hash);
  const std::optional<nlohmann::json>& checksums = reference_checksums(run.reference_key);
  state.reference_checked = checksums.has_value();
  // Records written before reference checksums are taken as measured against the stored copy.
  if (checksums && state.record.contains("reference_images") && state.record["reference_images"] != *checksums) {
    state.kind = RunState::Kind::other_copy;
    if (warn)
      fmt::print(stderr, "warning: run {} ({}) was measured against another copy of reference {} than the one stored "
                 "(it was computed again since); measuring the run again\n",
                 run.label, run.key, run.reference_key);
  } else if (reference_content_differs(run)) {
    // That reference is computed again before the runs, and this run is measured against the new one.
    state.kind = RunState::Kind::other_content;
    if (warn)
      fmt::print(stderr, "warning: run {} ({}) was measured against a reference computed for other scene content (a "
                 "mesh or environment map the scene names has changed since); measuring the run again\n",
                 run.label, run.key);
  } else if (measured_against_other_reference(state.record, run.reference_key)) {
    // Its reference settings (or scene) changed since: the variant has another reference now.
    state.kind = RunState::Kind::stale;
    if (warn)
      fmt::print(stderr, "warning: run {} ({}) was measured against reference {}, but its variant's reference is now {} "
                 "(the reference settings or the scene changed); measuring the run again\n",
                 run.label, run.key, state.record.value("reference_key", ""), run.reference_key);
  } else if (stored_with_fewer_seeds(state.record, run.seeds)) {
    const int stored_seeds = stored_seed_count(state.record);
    // The key is the same whatever `seeds` says: a record of fewer seeds is measured again with all of them.
    state.kind = RunState::Kind::fewer_seeds;
    if (warn)
      fmt::print(stderr, "warning: run {} ({}) was measured with {} seed{}, the experiment asks for {}; measuring the run "
                 "again\n",
                 run.label, run.key, stored_seeds, stored_seeds == 1 ? "" : "s", run.seeds);
  } else {
    state.kind = RunState::Kind::current;
  }
  return state;
}

std::optional<RunClaim> ResultStore::still_to_run(const RunAddress& run, const RunState& seen, bool replace,
                                                  StoreLock lock) {
  const StoredRun now = inspect_stored_run(paths_.run(experiment_, run.key));
  const bool to_run = now.state != StoredRun::State::stored || (replace && now.record_hash == seen.record_hash);
  if (!to_run) return std::nullopt;
  return RunClaim{run, std::move(lock)};
}

std::optional<RunClaim> ResultStore::try_claim(const RunAddress& run, const RunState& seen, bool replace, bool& held) {
  std::optional<StoreLock> lock = StoreLock::try_acquire(paths_.run_lock(experiment_, run.key));
  held = !lock;
  if (!lock) return std::nullopt;
  return still_to_run(run, seen, replace, std::move(*lock));
}

std::optional<RunClaim> ResultStore::claim(const RunAddress& run, const RunState& seen, bool replace) {
  StoreLock lock = StoreLock::acquire(paths_.run_lock(experiment_, run.key), fmt::format("run {} ({})", run.label, run.key));
  return still_to_run(run, seen, replace, std::move(lock));
}

void ResultStore::put(const RunClaim& claim, const std::vector<std::pair<std::string, std::string>>& images,
                      nlohmann::json record) {
  store_run_folder(paths_.run(experiment_, claim.run.key), images, std::move(record));
}

}  // namespace causticbench
