// The pieces of the report's plots (declared in plot_specs.h).
#include "reports/plot_specs.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "reports/report_parts.h"

namespace causticbench::report_detail {

bool all_positive(const std::vector<double>& values) {
  return !values.empty() && std::all_of(values.begin(), values.end(), [](double v) { return v > 0.0; });
}

json base_spec(const std::string& title, const std::string& subtitle) {
  json title_block = {{"text", title}, {"anchor", "start"}, {"fontSize", 15}};
  if (!subtitle.empty()) title_block["subtitle"] = subtitle;
  return {{"$schema", "https://vega.github.io/schema/vega-lite/v5.json"},
          {"title", title_block},
          {"width", 430},
          {"height", 300},
          {"config",
           {{"font", "system-ui, -apple-system, Segoe UI, Helvetica, Arial, sans-serif"},
            {"axis", {{"labelFontSize", 11}, {"titleFontSize", 12}, {"gridOpacity", 0.6}}},
            {"legend", {{"labelLimit", 360}, {"labelFontSize", 11}, {"titleFontSize", 12}}},
            {"title", {{"subtitleColor", "#555"}, {"subtitleFontSize", 11}}}}}};
}

json axis(const std::string& field, const std::string& title, bool log) {
  json encoding = {{"field", field}, {"type", "quantitative"}, {"title", title}};
  if (log) {
    encoding["scale"] = {{"type", "log"}};
    encoding["axis"] = {{"format", "~g"}};
  } else {
    encoding["scale"] = {{"zero", false}};
  }
  return encoding;
}

// Vega's tableau10 colours, given to the experiment's entries (Run::entry) in their order, so that an
// entry keeps its colour in every plot even when a plot shows only some of them. The rows' field is
// still called "method": it holds the entry, which is the method's name unless the entry has a label.
json method_colour(const Report& report, const std::set<std::string>& shown) {
  static const char* const palette[] = {"#4c78a8", "#f58518", "#e45756", "#72b7b2", "#54a24b",
                                        "#eeca3b", "#b279a2", "#ff9da6", "#9d755d", "#bab0ac"};
  json domain = json::array(), range = json::array();
  for (size_t m = 0; m < report.entries.size(); ++m) {
    if (!shown.empty() && !shown.count(report.entries[m])) continue;
    domain.push_back(report.entries[m]);
    range.push_back(palette[m % 10]);
  }
  return {
      {"field", "method"}, {"type", "nominal"}, {"title", "entry"}, {"scale", {{"domain", domain}, {"range", range}}}};
}

// A dashed horizontal rule at `value` with a label, as two layers.
std::vector<json> rule_layers(const std::string& field, double value, const std::string& text,
                              const std::string& colour) {
  json data = {{"values", json::array({{{field, value}, {"text", text}}})}};
  json y = {{"field", field}, {"type", "quantitative"}};
  return {{{"data", data},
           {"mark", {{"type", "rule"}, {"strokeDash", {6, 4}}, {"color", colour}, {"strokeWidth", 1.5}}},
           {"encoding", {{"y", y}}}},
          {{"data", data},
           {"mark",
            {{"type", "text"},
             {"align", "left"},
             {"baseline", "bottom"},
             {"dx", 4},
             {"dy", -3},
             {"color", colour},
             {"fontSize", 11}}},
           {"encoding", {{"y", y}, {"x", {{"value", 0}}}, {"text", {{"field", "text"}}}}}}};
}

json run_row(const Report& report, size_t i) {
  const Run& run = report.runs[i];
  json row = {{"key", run.key},
              {"method", run.entry},
              {"label", report.display(i)},
              {"knobs", run.changed_text()},
              {"frame_ms", run.frame_ms().value_or(NAN)},
              {"value", run.metric(report.primary).value_or(NAN)},
              {"front", report.on_front(i)}};
  if (report.multi()) {
    row["variant"] = run.variant;
    row["series"] = run.variant + " " + run.entry;
  }
  return row;
}

json tooltip(const Report& report) {
  json fields = json::array({{{"field", "label"}, {"title", "run"}},
                             {{"field", "method"}, {"title", "entry"}},
                             {{"field", "knobs"}, {"title", "knobs not at their defaults"}},
                             {{"field", "frame_ms"}, {"title", "frame ms (median)"}, {"format", ".4g"}},
                             {{"field", "value"}, {"title", report.primary}, {"format", ".4g"}}});
  if (report.multi()) fields.insert(fields.begin() + 2, json{{"field", "variant"}});
  return fields;
}

// The reference error rules of the error plots (primary metric relMSE only): one per variant whose
// reference has a positive floor, labelled with the variant's name when there are several. The floors
// are appended to `values` (for the choice of a log axis).
std::vector<json> floor_layers(const Report& report, const std::string& field, std::vector<double>& values) {
  std::vector<json> layers;
  if (report.primary != "relmse") return layers;
  for (const Variant& variant : report.variants) {
    if (!finite(variant.reference_error) || !(*variant.reference_error > 0.0)) continue;
    double floor = *variant.reference_error;
    values.push_back(floor);
    std::string text = report.multi() ? fmt::format("reference error {} {}", variant.name, num(floor))
                                      : "reference error " + num(floor);
    for (json& layer : rule_layers(field, floor, text, "#666")) layers.push_back(layer);
  }
  return layers;
}

std::vector<BaselineRule> baseline_rules(const Report& report, const std::string& metric) {
  std::vector<BaselineRule> rules;
  for (const Variant& variant : report.variants) {
    for (const BaselineScores& baseline : variant.baselines) {
      auto found = baseline.values.find(metric);
      if (found == baseline.values.end() || !std::isfinite(found->second)) continue;
      const bool black = &baseline == &variant.baselines.front();
      rules.push_back({found->second,
                       fmt::format("{}{} {}", baseline.name, report.multi() ? " " + variant.name : "", num(found->second)),
                       black ? "#111" : "#b07d00"});
    }
  }
  return rules;
}

std::vector<json> baseline_layers(const std::vector<BaselineRule>& rules, const std::string& field, bool log) {
  std::vector<json> layers;
  for (const BaselineRule& rule : rules) {
    if (log && !(rule.value > 0.0)) continue;
    for (json& layer : rule_layers(field, rule.value, rule.text, rule.colour)) layers.push_back(layer);
  }
  return layers;
}

// Points of several variants are told apart by their shape.
void add_variant_shape(const Report& report, json& encoding) {
  if (!report.multi()) return;
  json names = json::array();
  for (const Variant& variant : report.variants) names.push_back(variant.name);
  encoding["shape"] = {{"field", "variant"}, {"type", "nominal"}, {"title", "variant"}, {"scale", {{"domain", names}}}};
}

}  // namespace causticbench::report_detail
