// The study's summary (`causticbench summarize`): one page across several experiments' stored results —
// per scene the best method and knobs per frame budget, per method where it wins and where it fails, the
// cost model with break-even frame counts, and every claim with its verdict. Each experiment is read and
// compared exactly as its own report reads it (reports/report_model.h); what the page shows and how it is
// computed: docs/reports.md, "The study's summary".
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "reports/claim_verdicts.h"

namespace causticbench {

struct SummaryFiles {
  std::string html, markdown, json;  // the paths written
  size_t experiments = 0, scenes = 0;  // scenes: experiment variants with a measured run
  ClaimCounts claims;  // every experiment's claims, by verdict
  std::vector<std::string> headlines;  // per scene, the best method of the largest budget (plain text)
};

// Reads every folder (an experiment's results folder, RESULTS/<experiment>) and writes summary.html,
// summary.md and summary.json into `out_folder` (created when missing). Everything is read before
// anything is written: an input that is not an experiment folder, or one named twice, throws InputError
// and leaves `out_folder` as it was.
SummaryFiles write_summary(const std::vector<std::string>& experiment_folders, const std::string& out_folder);

}  // namespace causticbench
