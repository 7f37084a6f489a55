// Which runs of an experiment `causticbench run` has to do: those of its shard and filter that the
// result store (store/result_store.h) does not hold as current, or all of them with --force. What one
// process selects another may be doing: a selected run is run only once the store grants its claim
// (ResultStore::try_claim), so that processes sharing a results folder never run it twice.
#pragma once

#include <vector>

#include "experiments/experiment.h"
#include "experiments/runner.h"
#include "store/result_store.h"

namespace causticbench {

struct PendingRun {
  const RunSpec* run = nullptr;
  // What the store held when it was selected; `replace_stored`: that stored copy is to be replaced
  // (--force, or it is due again), as long as it is still the copy seen.
  RunState seen;
  bool replace_stored = false;
};

struct RunSelection {
  std::vector<PendingRun> pending;
  size_t selected = 0, stored = 0;
  // Stored runs whose reference was not stored when they were looked up: looked up again once it is.
  std::vector<PendingRun> unverified;
};

// The store's address of a run: its key and label, its variant's reference and scene content.
RunAddress run_address(const Experiment& experiment, const RunSpec& run);

// Selects the runs to do (phase 1 of the store's questions); with --dry-run also prints each selected
// run as stored or pending.
RunSelection select_runs(const Experiment& experiment, const RunOptions& options, ResultStore& store);

// Phase 2, after the references of `checked_variants` are stored: their unverified runs looked up again;
// those measured against another copy move to `pending`.
void recheck_against_references(const Experiment& experiment, const std::vector<size_t>& checked_variants,
                                ResultStore& store, RunSelection& selection);

}  // namespace causticbench
