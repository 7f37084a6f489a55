#include "experiments/run_selection.h"

#include <algorithm>

#include <fmt/format.h>

#include "experiments/reference_frames.h"

namespace causticbench {

namespace {

// The stored reference checksums of each variant, read once.
class ReferenceChecksums {
 public:
  ReferenceChecksums(const Experiment& experiment, const ResultPaths& paths) : experiment_(experiment), paths_(paths) {}
  const std::optional<nlohmann::json>& of(size_t variant) {
    auto it = cache_.find(variant);
    if (it == cache_.end())
      it = cache_.emplace(variant, stored_reference_checksums(paths_, experiment_.variants.at(variant).reference_key,
                                                              experiment_.frames)).first;
    return it->second;
  }
  bool content_differs(size_t variant) {
    auto it = content_differs_.find(variant);
    if (it == content_differs_.end())
      it = content_differs_.emplace(variant, stored_reference_content_differs(paths_, experiment_.variants.at(variant),
                                                                              experiment_.frames)).first;
    return it->second;
  }

 private:
  const Experiment& experiment_;
  const ResultPaths& paths_;
  std::map<size_t, std::optional<nlohmann::json>> cache_;
  std::map<size_t, bool> content_differs_;
};

// Whether a stored run was measured against another copy of its reference than `stored_checksums`
// (records written before reference checksums are taken as measured against the stored one).
bool measured_against_another_copy(const StoredRun& stored, const nlohmann::json& stored_checksums) {
  const nlohmann::json& record = stored.record;
  return record.contains("reference_images") && record["reference_images"] != stored_checksums;
}

void warn_other_copy(const Experiment& experiment, const RunSpec& run) {
  fmt::print(stderr, "warning: run {} ({}) was measured against another copy of reference {} than the one stored "
             "(it was computed again since); measuring the run again\n",
             run.label, run.key, experiment.variants.at(run.variant).reference_key);
}

}  // namespace

RunSelection select_runs(const Experiment& experiment, const RunOptions& options, const ResultPaths& paths) {
  RunSelection selection;
  ReferenceChecksums references(experiment, paths);
  for (size_t i = 0; i < experiment.runs.size(); ++i) {
    const RunSpec& run = experiment.runs[i];
    if (options.shard_count > 1 && options.shard_of.at(run.key) != options.shard_index) continue;
    if (!options.filter.empty() && !run_matches_filter(experiment, run, options.filter)) continue;
    ++selection.selected;
    StoredRun stored = inspect_stored_run(paths.run(experiment.name, run.key));
    PendingRun pending{&run, false, ""};
    bool to_do = true;
    if (stored.state == StoredRun::State::damaged) {
      fmt::print(stderr, "warning: {}; the run is not counted as stored and is measured again\n", stored.problem);
    } else if (stored.state == StoredRun::State::stored) {
      const std::optional<nlohmann::json>& checksums = references.of(run.variant);
      bool other_copy = checksums && measured_against_another_copy(stored, *checksums);
      if (other_copy) warn_other_copy(experiment, run);
      // Its reference was computed for other scene content (an asset edited in place): that reference is
      // computed again before the runs, and this run is measured against the new one.
      bool content_changed = !other_copy && references.content_differs(run.variant);
      if (content_changed)
        fmt::print(stderr, "warning: run {} ({}) was measured against a reference computed for other scene content (a "
                   "mesh or environment map the scene names has changed since); measuring the run again\n",
                   run.label, run.key);
      // Its reference settings (or scene) changed since: the variant has another reference now.
      const std::string& current = experiment.variants.at(run.variant).reference_key;
      bool stale = !other_copy && !content_changed && measured_against_other_reference(stored.record, current);
      if (stale)
        fmt::print(stderr, "warning: run {} ({}) was measured against reference {}, but its variant's reference is now {} "
                   "(the reference settings or the scene changed); measuring the run again\n",
                   run.label, run.key, stored.record.value("reference_key", ""), current);
      to_do = options.force || other_copy || content_changed || stale;
      pending = {&run, to_do, stored.record_hash};
      if (!checksums && !to_do) selection.unverified.push_back({&run, std::move(stored)});
    }
    if (options.dry_run) fmt::print("{}  {:<8} {}\n", run.key, to_do ? "pending" : "stored", run.label);
    if (to_do) selection.pending.push_back(pending);
    else ++selection.stored;
  }
  return selection;
}

void recheck_against_references(const Experiment& experiment, const ResultPaths& paths,
                                const std::vector<size_t>& checked_variants, RunSelection& selection) {
  ReferenceChecksums references(experiment, paths);
  std::vector<std::pair<const RunSpec*, StoredRun>> still_unverified;
  for (auto& [run, stored] : selection.unverified) {
    bool checked = std::count(checked_variants.begin(), checked_variants.end(), run->variant) > 0;
    const std::optional<nlohmann::json>& checksums = references.of(run->variant);
    if (checked && checksums && measured_against_another_copy(stored, *checksums)) {
      warn_other_copy(experiment, *run);
      selection.pending.push_back({run, true, stored.record_hash});
      --selection.stored;
    } else {
      still_unverified.push_back({run, std::move(stored)});
    }
  }
  selection.unverified = std::move(still_unverified);
}

bool still_to_run(const Experiment& experiment, const ResultPaths& paths, const PendingRun& pending) {
  StoredRun stored = inspect_stored_run(paths.run(experiment.name, pending.run->key));
  if (stored.state != StoredRun::State::stored) return true;
  return pending.replace_stored && stored.record_hash == pending.replaced_record_hash;
}

}  // namespace causticbench
