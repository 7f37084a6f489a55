// The one registry of quantities (metrics/quantities.h): the measured quantities (every metric, the
// runner's timings and sizes) and every counter a registered method declares (MethodInfo::counters).
// Claims, filters, tables, Pareto fronts, trade-off plots and the equal-time and equal-error views look
// their quantities up here; an unknown name is refused with the closest known one.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "metrics/quantities.h"

namespace causticbench {

// Measured quantities first, then each method's counters in registry order (a counter two methods
// share, photons_emitted, once). Built on each call: tests register methods of their own.
std::vector<QuantityInfo> quantity_registry();
std::vector<std::string> quantity_names();

std::optional<QuantityInfo> find_quantity(const std::string& name);

// "one of the quantities frame_ms, render_ms, ... (did you mean 'frame_ms'?)": what an experiment's
// error names as expected for an unknown quantity.
std::string expected_quantity_text(const std::string& name, bool ranked_only);

// The registered quantity; throws InputError "<context>: unknown quantity 'x' (did you mean ...)" or, with
// `ranked_only`, when the quantity has no direction (receiver_pixels cannot be better or worse).
QuantityInfo require_quantity(const std::string& name, const std::string& context, bool ranked_only = true);

// By name, for the report's tables and captions: the registered quantity's direction; a name the
// registry does not know counts as lower-is-better (a cost), with no direction text.
bool quantity_better(const std::string& name, double a, double b);
std::string direction_text(const std::string& name);
std::string direction_arrow(const std::string& name);

}  // namespace causticbench
