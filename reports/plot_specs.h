// The pieces of the report's Vega-Lite plots (plots.cpp, tradeoff_plots.cpp): the base specification,
// axes, the methods' fixed colours, dashed rules, one run as a data row with its tooltip, the
// reference errors and the variant's point shape. Internal to reports/.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "reports/report_model.h"

namespace causticbench::report_detail {

bool all_positive(const std::vector<double>& values);
json base_spec(const std::string& title, const std::string& subtitle);
json axis(const std::string& field, const std::string& title, bool log);
// Vega's tableau10 colours, given to the methods in their order, so that a method keeps its colour in
// every plot even when a plot shows only some of the methods.
json method_colour(const Report& report, const std::set<std::string>& shown = {});
// A dashed horizontal rule at `value` with a label, as two layers.
std::vector<json> rule_layers(const std::string& field, double value, const std::string& text, const std::string& colour);
// One run: key, method, label, knobs, frame_ms, value (the primary metric), front (its method's).
json run_row(const Report& report, size_t run);
json tooltip(const Report& report);
// The reference error rules of the error plots (primary metric relMSE only), one per variant with
// a positive floor; the floors are appended to `values` (for the choice of a log axis).
std::vector<json> floor_layers(const Report& report, const std::string& field, std::vector<double>& values);
// The baselines' values of `metric` (metrics/baselines.h), one rule per variant and baseline with a value.
struct BaselineRule {
  double value;
  std::string text;
  std::string colour;
};
std::vector<BaselineRule> baseline_rules(const Report& report, const std::string& metric);
// Their dashed rules; on a log axis a rule at a value <= 0 cannot be drawn and is left out.
std::vector<json> baseline_layers(const std::vector<BaselineRule>& rules, const std::string& field, bool log);
// Points of several variants are told apart by their shape.
void add_variant_shape(const Report& report, json& encoding);

}  // namespace causticbench::report_detail
