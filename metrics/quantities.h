// What a run measures, as one kind of thing: every metric (metrics.h), every timing and size the runner
// records, and every counter a method declares (MethodInfo::counters), each with its unit and which way
// is better. Claims, run filters, tables, Pareto fronts, trade-off plots and the equal-time and
// equal-error views all take their quantities from here (methods/quantity_registry.h assembles
// the full list with the methods' counters); docs/metrics.md, "Quantities", lists them.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace causticbench {

enum class QuantityKind {
  metric,   // an error metric of E_c against the reference (metrics.h)
  timing,   // a time the runner or the method measured
  size,     // bytes
  count,    // a method's counter (photons emitted, light samples, ...) or the scene's pixels
};

enum class QuantityDirection {
  lower,   // lower is better (errors, times, sizes, costs)
  higher,  // higher is better (psnr, ssim)
  target,  // closest to `target` is better (energy_ratio: 1)
  none,    // a property of the scene, not of the method's quality or cost (receiver_pixels): no ranking
};

// Where a run record holds the value (store/run_record.h, RunRecord::quantity).
enum class QuantitySource {
  metrics,   // "metrics": the mean over frames (or the sequence's value)
  timings,   // "timings": the median over timed passes (`field` names it, e.g. frame_ms_median)
  prepare,   // "prepare": the build's own time (prepare_seconds)
  record,    // a top-level number of the record (`field`: memory_bytes, peak_rss_bytes, receiver_pixels, lost_flux)
  counters,  // "counters": the method's counter of that name
};

struct QuantityInfo {
  std::string name;        // as experiment files, filters and report columns spell it
  QuantityKind kind = QuantityKind::metric;
  QuantityDirection direction = QuantityDirection::lower;
  std::optional<double> target;  // direction target only
  std::string unit;        // "ms", "s", "bytes", "" (dimensionless), ...
  std::string definition;  // one line, for --help, docs and report captions
  QuantitySource source = QuantitySource::metrics;
  std::string field;       // the record field when it is not `name` (timings: "frame_ms_median")
};

// The metrics and the runner's own timings and sizes, in the order reports list them; the methods'
// counters are added by quantity_registry() (methods/quantity_registry.h).
const std::vector<QuantityInfo>& measured_quantities();

// A counter a method declares in its MethodInfo: a cost, so lower is better.
QuantityInfo counter_quantity(std::string name, std::string unit, std::string definition,
                              QuantityKind kind = QuantityKind::count);

// Whether value a is strictly better than b: closer to the target, larger or smaller. NaN is never
// better than anything and anything else is better than NaN. A quantity without a direction ranks
// nothing (always false).
bool quantity_better(const QuantityInfo& quantity, double a, double b);

// "lower is better", "higher is better", "best = 1", "" (no direction): for captions and notes.
std::string direction_text(const QuantityInfo& quantity);
// "↓", "↑", "→1", "": for table headers.
std::string direction_arrow(const QuantityInfo& quantity);
// "frame_ms (ms, lower is better)": for axis titles.
std::string quantity_title(const QuantityInfo& quantity);

}  // namespace causticbench
