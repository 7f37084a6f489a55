#include "reports/light_accounting.h"

#include "reports/report_model.h"

namespace causticbench::report_detail {

std::optional<LightAccount> account_for_run(const Report& report, const Run& run) {
  if (run.empty_reference) return std::nullopt;
  return account_for_record(report.variants.at(run.variant_index).reference, run.record);
}

}  // namespace causticbench::report_detail
