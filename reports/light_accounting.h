// The report's side of where each run's light went (experiments/light_account.h holds the account and
// its tolerance): each run of a report against its variant's reference.
#pragma once

#include <optional>

#include "experiments/light_account.h"

namespace causticbench::report_detail {

struct Report;
struct Run;
// The account of a report's run against its variant's reference record (account_for_record).
std::optional<LightAccount> account_for_run(const Report& report, const Run& run);

}  // namespace causticbench::report_detail
