// One `methods:` entry of an experiment file read into runs (docs/experiment-format.md): its fixed knobs
// by phase, its `sweep` (cartesian) and `zip` (paired) lists, the variants it runs on, the count of runs
// it adds (refused beyond max_runs before anything is expanded), and its resolved, keyed run specs.
#pragma once

#include <cstdint>
#include <set>
#include <string>

#include "core/config.h"
#include "experiments/experiment.h"

namespace causticbench {

// What the experiment's entries have added so far.
struct RunCount {
  int64_t max_runs = kDefaultMaximumRuns;
  double counted = 0.0;        // runs the entries read so far expand to (before duplicates are dropped)
  std::set<std::string> keys;  // of the runs added: the same run twice is kept once
};

// Appends the entry's runs to experiment.runs (its variants, frames, repetitions, pixel_samples and
// reference are read already). InputError with file, line and key on any defect.
void add_method_entry(const ConfigNode& entry, Experiment& experiment, RunCount& count);

}  // namespace causticbench
