// `causticbench report --recompute-metrics`: every metric of every stored ok run computed again from
// the stored images (the run's frame_NNNN.exr, its reference's frame and G-buffer), after a metric was
// added or fixed, without running any method. The experiment's metrics (experiment.json "metrics") are
// scored on the images the record names, each checked against the checksums the record holds (its own
// images and the reference images it was measured against); each record is rewritten in one atomic
// step under the run's lock, so a concurrent `run` and a killed recompute leave every record whole.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace causticbench {

struct RecomputeSummary {
  size_t recomputed = 0;  // records rewritten
  size_t skipped = 0;     // failed, missing or damaged runs, and runs whose images no longer match
  std::vector<std::string> problems;  // why each skipped ok run was skipped
};

// Throws InputError when `experiment_folder` has no experiment.json.
RecomputeSummary recompute_metrics(const std::string& experiment_folder);

}  // namespace causticbench
