// Measuring a run with several seeds (an experiment's `seeds: N`; docs/experiment-format.md). A run is
// stochastic when its resolved knobs have a `seed` (every random choice of a method draws from it,
// docs/adding-a-method.md); it is measured with its own seed and the next N - 1, each a full run (the
// seed a build knob: a build of its own). Its record keeps its key and its own seed's images as its
// frames, holds every seed's frames and metrics under "seeds", and reports each metric as the mean over
// the seeds with a 95 % interval (metrics/confidence.h). A deterministic run is measured once; its
// interval has zero width.
#pragma once

#include <string>
#include <vector>

#include "experiments/experiment.h"
#include "experiments/run_measurement.h"
#include "store/run_record.h"

namespace causticbench {

// Whether the run's output depends on a seed: its knobs have one.
bool stochastic(const RunSpec& run);

// The seeds the run is measured with: the experiment's `seeds` when it is stochastic, else 1.
int seed_count(const Experiment& experiment, const RunSpec& run);

// The run with its seed knob moved `index` seeds on (base + index), in its knobs and in the phase that
// holds it; key and label unchanged. Index 0 is the run itself.
RunSpec seed_replica(const RunSpec& run, int index);

// The file of a frame of a seed other than the run's own: "seed<value>_NNNN.exr"; and of the per-pixel
// standard deviation over the seeds: "stddev_NNNN.exr".
std::string seed_image_file(int64_t seed, int frame);
std::string stddev_image_file(int frame);

// The run's outcome from its seeds' outcomes, the run's own first: its own record and images, with every
// seed's frames, metrics and images under "seeds", the per-pixel standard deviation images, and the
// metrics as the means over the seeds (aggregate_seeds). A seed that failed fails the run, naming it.
RunOutcome combine_seeds(std::vector<RunOutcome> seeds);

// The record's metrics, its frames' metrics and the intervals, from record.seeds' runs: each the mean
// over the seeds, undefined where it is undefined on any seed (with that seed's reason). `report
// --recompute-metrics` calls it after scoring every seed again.
void aggregate_seeds(RunRecord& record);

}  // namespace causticbench
