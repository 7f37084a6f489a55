// The record of one run (docs/results-format.md, runs/<run_key>/record.json): which run it is, its
// metrics per frame and over the sequence against the reference it was measured against (and that
// reference's checksums and convergence), its timings and its method's counters.
#pragma once

#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "experiments/experiment.h"
#include "experiments/reference_frames.h"
#include "methods/lifecycle.h"

namespace causticbench {

struct RunOutcome {
  nlohmann::json record;
  std::vector<std::pair<int, Image>> images;
};

// The fields that say which run a record is, for finished and failed runs alike.
nlohmann::json run_identity(const Experiment& experiment, const RunSpec& run);

// Measures one run from its share of a played sequence: metrics per frame against the reference,
// flicker over the sequence, timings per frame and over all frames and passes. `empty_reference` lists
// the frames whose reference has no caustic in view (an experiment with empty_reference_expected): those
// frames are not scored, and the record says so.
RunOutcome measure_run(const Experiment& experiment, const RunSpec& run, const CausticMethod& method,
                       const PrepareOutcome& prepare, SequenceOutput&& output, const VariantFrames& variant_frames,
                       const std::vector<FramePresence>& empty_reference);

}  // namespace causticbench
