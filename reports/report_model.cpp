// The run's resolved knobs, which the paper table (tables.cpp), the claims (claims.cpp) and the sweep
// plots match and group by.
#include "reports/report_model.h"

#include "experiments/experiment.h"

namespace causticbench::report_detail {

json run_knobs(const Run& run) {
  json knobs = run.record.knobs();
  knobs["variant"] = run.variant;
  return knobs;
}

}  // namespace causticbench::report_detail
