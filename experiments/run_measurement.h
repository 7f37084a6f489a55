// Measuring one run: its record (run_record.h) from its share of a played sequence, with metrics per
// frame and over the sequence against the reference it was measured against (and that reference's
// checksums, convergence and settings), its timings and its method's counters; and the scoring step
// alone, which `report --recompute-metrics` repeats on the stored images.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/image.h"
#include "experiments/experiment.h"
#include "experiments/reference_frames.h"
#include "store/run_record.h"
#include "methods/lifecycle.h"

namespace causticbench {

struct RunOutcome {
  RunRecord record;
  std::vector<std::pair<int, Image>> images;  // frame -> E_c, stored as frame_NNNN.exr
  // More images by file name: the other seeds' frames and the standard deviations over the seeds
  // (experiments/seed_replicas.h).
  std::vector<std::pair<std::string, Image>> more_images;
};

// The fields that say which run a record is, for finished and failed runs alike (status ok, no frames).
RunRecord run_identity(const Experiment& experiment, const RunSpec& run);

// One frame to score: the method's E_c, the reference's, the receiver mask, and, when the reference
// has no caustic in view on it (an experiment with empty_reference_expected), why.
struct ScoredFrame {
  int frame = 0;
  const Image* test = nullptr;
  const Image* reference = nullptr;
  const std::vector<uint8_t>* mask = nullptr;
  std::optional<std::string> empty_reference;
};

// Sets the metrics of record.frames (matched by frame number, in `frames`' order) and of the whole run:
// each per-frame metric of `metrics` per frame, the run's value its mean over frames (nonfinite_pixels:
// the sum), undefined when undefined on any frame; temporal_flicker over the sequence when `metrics`
// names it and there are several frames. Returns the count of non-finite masked pixels.
size_t score_run(RunRecord& record, const std::vector<std::string>& metrics, const std::vector<ScoredFrame>& frames);

// Measures one run from its share of a played sequence. `empty_reference` lists the frames whose
// reference has no caustic in view (an experiment with empty_reference_expected): those frames are not
// scored, and the record says so.
RunOutcome measure_run(const Experiment& experiment, const RunSpec& run, const CausticMethod& method,
                       const PrepareOutcome& prepare, SequenceOutput&& output, const VariantFrames& variant_frames,
                       const std::vector<FramePresence>& empty_reference);

}  // namespace causticbench
