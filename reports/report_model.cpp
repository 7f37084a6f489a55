// Lookups on one run that both the paper table (tables.cpp) and the claims (claims.cpp) make: the value
// of a named quantity, and the run's resolved knobs.
#include "reports/report_model.h"

#include "experiments/experiment.h"

namespace causticbench::report_detail {

std::optional<double> ours(const Run& run, const std::string& column) { return run.quantity(column); }

json run_knobs(const Run& run) {
  json knobs = run.record.knobs();
  knobs["variant"] = run.variant;
  return knobs;
}

}  // namespace causticbench::report_detail
