#include "experiments/run_selection.h"

#include <algorithm>

#include <fmt/format.h>

#include "experiments/seed_replicas.h"

namespace causticbench {

RunAddress run_address(const Experiment& experiment, const RunSpec& run) {
  const SceneVariant& variant = experiment.variants.at(run.variant);
  return RunAddress{run.key, run.label, variant.reference_key, variant.content_hash, seed_count(experiment, run)};
}

RunSelection select_runs(const Experiment& experiment, const RunOptions& options, ResultStore& store) {
  RunSelection selection;
  for (const RunSpec& run : experiment.runs) {
    if (options.shard_count > 1 && options.shard_of.at(run.key) != options.shard_index) continue;
    if (!options.filter.empty() && !run_matches_filter(experiment, run, options.filter)) continue;
    ++selection.selected;
    RunState state = store.look_up(run_address(experiment, run));
    const bool to_run = state.to_run(options.force);
    const bool unverified = !to_run && !state.reference_checked;
    PendingRun pending{&run, std::move(state), false};
    pending.replace_stored = to_run && pending.seen.stored();
    if (options.dry_run) fmt::print("{}  {:<8} {}\n", run.key, to_run ? "pending" : "stored", run.label);
    if (to_run) {
      selection.pending.push_back(std::move(pending));
    } else {
      ++selection.stored;
      if (unverified) selection.unverified.push_back(std::move(pending));
    }
  }
  return selection;
}

void recheck_against_references(const Experiment& experiment, const std::vector<size_t>& checked_variants,
                                ResultStore& store, RunSelection& selection) {
  store.references_changed();
  std::vector<PendingRun> still_unverified;
  for (PendingRun& entry : selection.unverified) {
    const bool checked = std::count(checked_variants.begin(), checked_variants.end(), entry.run->variant) > 0;
    RunState state = checked ? store.look_up(run_address(experiment, *entry.run)) : RunState{};
    if (checked && state.kind == RunState::Kind::other_copy) {
      selection.pending.push_back({entry.run, std::move(state), true});
      --selection.stored;
    } else {
      still_unverified.push_back(std::move(entry));
    }
  }
  selection.unverified = std::move(still_unverified);
}

}  // namespace causticbench
