// Metric directions for the report (declared in metric_directions.h), taken from the metric registry.
#include "reports/metric_directions.h"

#include <cmath>

#include "reports/report_text.h"

namespace causticbench::report_detail {

const MetricInfo* metric_info(const std::string& name) {
  for (const MetricInfo& info : metric_registry()) {
    if (info.name == name) return &info;
  }
  return nullptr;
}

bool better(const std::string& metric, double a, double b) {
  if (const MetricInfo* info = metric_info(metric)) return metric_better(*info, a, b);
  if (std::isnan(a)) return false;
  if (std::isnan(b)) return true;
  return a < b;
}

std::string direction_text(const std::string& metric) {
  const MetricInfo* info = metric_info(metric);
  if (!info) return "lower is better";
  if (info->target) return "best = " + num(*info->target);
  return info->higher_is_better ? "higher is better" : "lower is better";
}

std::string direction_arrow(const std::string& metric) {
  const MetricInfo* info = metric_info(metric);
  if (info && info->target) return "\u2192" + num(*info->target);
  return info && info->higher_is_better ? "\u2191" : "\u2193";
}

}  // namespace causticbench::report_detail
