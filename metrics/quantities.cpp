// The measured quantities (declared in quantities.h): the metric registry's metrics with their
// directions, then what the runner itself records about every run.
#include "metrics/quantities.h"

#include <cmath>

#include <fmt/format.h>

#include "metrics/metrics.h"

namespace causticbench {

namespace {

QuantityInfo from_metric(const MetricInfo& metric) {
  QuantityInfo quantity;
  quantity.name = metric.name;
  quantity.kind = QuantityKind::metric;
  quantity.direction = metric.target ? QuantityDirection::target
                                     : (metric.higher_is_better ? QuantityDirection::higher : QuantityDirection::lower);
  quantity.target = metric.target;
  quantity.unit = metric.unit;
  quantity.definition = metric.definition;
  quantity.source = QuantitySource::metrics;
  return quantity;
}

QuantityInfo runner_quantity(std::string name, QuantityKind kind, QuantityDirection direction, std::string unit,
                             std::string definition, QuantitySource source, std::string field) {
  QuantityInfo quantity;
  quantity.name = std::move(name);
  quantity.kind = kind;
  quantity.direction = direction;
  quantity.unit = std::move(unit);
  quantity.definition = std::move(definition);
  quantity.source = source;
  quantity.field = std::move(field);
  return quantity;
}

std::vector<QuantityInfo> make_measured_quantities() {
  std::vector<QuantityInfo> all;
  for (const MetricInfo& metric : metric_registry()) all.push_back(from_metric(metric));
  using K = QuantityKind;
  using D = QuantityDirection;
  using S = QuantitySource;
  all.push_back(runner_quantity("frame_ms", K::timing, D::lower, "ms",
                                "median over timed passes and frames of update + render time of one frame",
                                S::timings, "frame_ms_median"));
  all.push_back(runner_quantity("render_ms", K::timing, D::lower, "ms",
                                "median over timed passes and frames of render() (E_c at the G-buffer points)",
                                S::timings, "render_ms_median"));
  all.push_back(runner_quantity("update_ms", K::timing, D::lower, "ms",
                                "median over timed passes and frames of update() (per-frame work before render)",
                                S::timings, "update_ms_median"));
  all.push_back(runner_quantity("gpu_render_ms", K::timing, D::lower, "ms",
                                "median kernel time from GPU timestamp queries (Vulkan backends only)", S::timings,
                                "gpu_render_ms_median"));
  all.push_back(runner_quantity("prepare_seconds", K::timing, D::lower, "s",
                                "time prepare() took to build what the method precomputes (for a loaded build: when "
                                "it was computed)",
                                S::prepare, "prepare_seconds"));
  all.push_back(runner_quantity("memory_bytes", K::size, D::lower, "bytes",
                                "the method's own memory after prepare() (its precomputed data and buffers)", S::record,
                                "memory_bytes"));
  all.push_back(runner_quantity("peak_rss_bytes", K::size, D::lower, "bytes",
                                "peak resident memory of the process when the run was measured", S::record,
                                "peak_rss_bytes"));
  all.push_back(runner_quantity("lost_flux", K::count, D::lower, "fraction",
                                "the largest fraction over the frames of the caustic flux the method's configuration "
                                "cannot represent (docs/metrics.md, \"Lost flux\"): its own count, measured untimed",
                                S::record, "lost_flux"));
  all.push_back(runner_quantity("receiver_pixels", K::count, D::none, "pixels",
                                "receiver pixels of the G-buffer in the first frame (the scene's, not the method's)",
                                S::record, "receiver_pixels"));
  return all;
}

}  // namespace

const std::vector<QuantityInfo>& measured_quantities() {
  static const std::vector<QuantityInfo> quantities = make_measured_quantities();
  return quantities;
}

QuantityInfo counter_quantity(std::string name, std::string unit, std::string definition, QuantityKind kind) {
  QuantityInfo quantity;
  quantity.name = std::move(name);
  quantity.kind = kind;
  quantity.direction = QuantityDirection::lower;
  quantity.unit = std::move(unit);
  quantity.definition = std::move(definition);
  quantity.source = QuantitySource::counters;
  return quantity;
}

bool quantity_better(const QuantityInfo& quantity, double a, double b) {
  if (quantity.direction == QuantityDirection::none) return false;
  if (std::isnan(a)) return false;
  if (std::isnan(b)) return true;
  switch (quantity.direction) {
    case QuantityDirection::target: return std::abs(a - *quantity.target) < std::abs(b - *quantity.target);
    case QuantityDirection::higher: return a > b;
    default: return a < b;
  }
}

std::string direction_text(const QuantityInfo& quantity) {
  switch (quantity.direction) {
    case QuantityDirection::lower: return "lower is better";
    case QuantityDirection::higher: return "higher is better";
    case QuantityDirection::target: return fmt::format("best = {}", *quantity.target);
    case QuantityDirection::none: return "";
  }
  return "";
}

std::string direction_arrow(const QuantityInfo& quantity) {
  switch (quantity.direction) {
    case QuantityDirection::lower: return "\u2193";
    case QuantityDirection::higher: return "\u2191";
    case QuantityDirection::target: return fmt::format("\u2192{}", *quantity.target);
    case QuantityDirection::none: return "";
  }
  return "";
}

std::string quantity_title(const QuantityInfo& quantity) {
  std::string direction = direction_text(quantity);
  std::string inside = quantity.unit;
  if (!direction.empty()) inside += (inside.empty() ? "" : ", ") + direction;
  return inside.empty() ? quantity.name : quantity.name + " (" + inside + ")";
}

}  // namespace causticbench
