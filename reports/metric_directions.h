// Which way each metric is better, as the report compares and labels values: lower, higher, or closest
// to a target (the metric registry of metrics/metrics.h), with a fallback for names it does not know.
// Internal to reports/ (see report_model.h).
#pragma once

#include <string>

#include "metrics/metrics.h"

namespace causticbench::report_detail {

// The registered metric of that name, or null.
const MetricInfo* metric_info(const std::string& name);

// Whether value a of the metric is strictly better than b. Unknown metrics (none should exist, and the
// claims' timings and sizes, which are lower-is-better) count as lower-is-better, NaN as worst.
bool better(const std::string& metric, double a, double b);

// "lower is better", "higher is better" or "best = 1": for captions and table header notes.
std::string direction_text(const std::string& metric);

// "↓", "↑" or "→1": for table headers.
std::string direction_arrow(const std::string& metric);

}  // namespace causticbench::report_detail
