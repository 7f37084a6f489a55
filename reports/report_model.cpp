// Lookups on one run that both the paper table (tables.cpp) and the claims (claims.cpp) make: the value
// of a named quantity, and the run's resolved knobs.
#include "reports/report_model.h"

#include "experiments/experiment.h"

namespace causticbench::report_detail {

std::optional<double> ours(const Run& run, const std::string& column) {
  if (auto value = run.timing(column + "_median")) return value;
  if (auto value = run.timing(column)) return value;
  if (auto value = run.metric(column)) return value;
  if (auto value = run.top(column)) return value;
  return number(member(run.record, "counters"), column);
}

json run_knobs(const Run& run) {
  json knobs = record_knobs(run.record);
  knobs["variant"] = run.variant;
  return knobs;
}

}  // namespace causticbench::report_detail
