// The experiment's report keys (declared in report_settings.h).
#include "experiments/report_settings.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/config.h"
#include "core/errors.h"
#include "methods/quantity_registry.h"
#include "methods/param_dict.h"
#include "methods/registry.h"
#include "metrics/metrics.h"

namespace causticbench {

namespace {

// A quantity named at `key` of `node` (or, for a list entry, by the entry itself): a metric the
// experiment measures, or a registered timing, size or counter; with `ranked`, one that is better one way.
std::string read_quantity(const ConfigNode& node, const std::string& key, const std::vector<std::string>& metrics,
                          bool ranked) {
  std::string name = key.empty() ? node.as_string() : node.string(key);
  auto fail = [&](const std::string& expected) {
    if (key.empty()) node.fail_here(expected, "'" + name + "'");
    node.fail(key, expected, "'" + name + "'");
  };
  std::optional<QuantityInfo> quantity = find_quantity(name);
  if (!quantity) fail(expected_quantity_text(name, ranked));
  if (quantity->kind == QuantityKind::metric && std::find(metrics.begin(), metrics.end(), name) == metrics.end())
    fail("a metric the experiment measures (metrics: " + join(metrics, ", ") + "), or a timing, size or counter");
  if (ranked && quantity->direction == QuantityDirection::none)
    fail(fmt::format("a quantity that is better one way ('{}' is a property of the scene)", name));
  return name;
}

// A list of positive, finite numbers in increasing order.
std::vector<double> read_increasing(const ConfigNode& root, const std::string& key, std::vector<double> fallback,
                                    double largest) {
  std::optional<ConfigNode> list = root.optional_child(key);
  if (!list) return fallback;
  if (!list->is_sequence() || list->size() == 0) root.fail(key, "a non-empty list of numbers", list->describe_value());
  std::vector<double> values;
  for (size_t i = 0; i < list->size(); ++i) {
    ConfigNode entry = list->at(i);
    double value = entry.as_number();
    if (!(value > 0.0) || !std::isfinite(value) || value > largest)
      entry.fail_here(fmt::format("a number in (0, {}]", largest), entry.describe_value());
    if (!values.empty() && value <= values.back())
      entry.fail_here(fmt::format("numbers in increasing order (after {})", values.back()), entry.describe_value());
    values.push_back(value);
  }
  return values;
}

nlohmann::json read_paper(const ConfigNode& node, const std::vector<std::string>& variants) {
  nlohmann::json paper = nlohmann::json::object();
  paper["title"] = node.string("title");
  paper["columns"] = nlohmann::json::array();
  ConfigNode columns = node.child("columns");
  for (size_t i = 0; i < columns.size(); ++i) {
    ConfigNode column = columns.at(i);
    std::string name = column.as_string();
    if (!find_quantity(name)) column.fail_here(expected_quantity_text(name, false), "'" + name + "'");
    paper["columns"].push_back(name);
  }
  paper["rows"] = nlohmann::json::array();
  ConfigNode rows = node.child("rows");
  for (size_t i = 0; i < rows.size(); ++i) {
    ConfigNode row = rows.at(i);
    nlohmann::json out;
    std::string method = row.string("method");
    const MethodInfo* info = nullptr;
    try {
      info = &find_method(method).info();  // a paper row for an unknown method is a typo
    } catch (const InputError& error) {
      throw InputError(fmt::format("{}: {}", row.location_of("method").describe(), error.what()));
    }
    out["method"] = method;
    out["match"] = nlohmann::json::object();
    if (std::optional<ConfigNode> match = row.optional_child("match")) {
      // Resolved like knobs, so that a typo is caught and values compare by type (100 == 1e2).
      // `variant: NAME` (one of the experiment's variants) picks the runs of one scene variant (a row per object of a table); the report
      // matches it by name. The other keys are knobs.
      std::optional<std::string> variant;
      if (match->has("variant")) {
        variant = match->child("variant").as_string();
        if (std::find(variants.begin(), variants.end(), *variant) == variants.end())
          match->fail("variant", "one of the experiment's variants (" + join(variants, ", ") + ")",
                      "'" + *variant + "'" + did_you_mean(*variant, variants));
      }
      ParamDict dict;
      for (const std::string& key : match->keys())
        if (key != "variant") dict.set(key, match->child(key).as_string(), match->child(key).location());
      nlohmann::json resolved = dict.resolve(info->params, method).to_json();
      for (const std::string& key : match->keys()) out["match"][key] = key == "variant" ? nlohmann::json(*variant) : resolved[key];
    }
    out["values"] = nlohmann::json::object();
    ConfigNode values = row.child("values");
    for (const std::string& key : values.keys()) out["values"][key] = values.child(key).as_number();
    out["note"] = row.string_or("note", "");
    row.finish();
    paper["rows"].push_back(out);
  }
  node.finish();
  return paper;
}

nlohmann::json read_claims(const ConfigNode& node, const std::vector<std::string>& metrics) {
  nlohmann::json claims = nlohmann::json::array();
  for (size_t i = 0; i < node.size(); ++i) {
    ConfigNode claim = node.at(i);
    nlohmann::json out;
    out["text"] = claim.string("text");
    std::string kind = claim.choice("kind", {"best", "better", "same", "linear", "ratio"});
    out["kind"] = kind;
    if (kind == "best") {
      out["metric"] = read_quantity(claim, "metric", metrics, true);
      out["among"] = claim.string("among");
      out["expect"] = claim.string("expect");
    } else if (kind == "better") {
      out["metric"] = read_quantity(claim, "metric", metrics, true);
      out["run"] = claim.string("run");
      out["than"] = claim.string("than");
    } else if (kind == "same") {
      // Any registered quantity: `same` compares values, it needs no better direction.
      out["metric"] = read_quantity(claim, "metric", metrics, false);
      out["run"] = claim.string("run");
      out["than"] = claim.string("than");
      // Equal to the last bit is no claim a measurement can make: a tolerance must be stated.
      if (!claim.has("relative_tolerance") && !claim.has("absolute_tolerance"))
        claim.fail_here("a relative_tolerance or an absolute_tolerance (or both) for kind same", "neither");
      out["relative_tolerance"] = claim.number_or("relative_tolerance", 0.0, 0.0, 1e6);
      out["absolute_tolerance"] = claim.number_or("absolute_tolerance", 0.0, 0.0, 1e300);
    } else if (kind == "ratio") {
      out["y"] = read_quantity(claim, "y", metrics, false);
      out["run"] = claim.string("run");
      out["than"] = claim.string("than");
      out["at_most"] = claim.number("at_most", 0.0, 1e12);  // the largest ratio that confirms the claim
    } else {
      out["x"] = claim.string("x");  // a knob or a quantity (receiver_pixels)
      out["y"] = read_quantity(claim, "y", metrics, false);
      out["among"] = claim.string("among");
      out["min_r2"] = claim.number_or("min_r2", 0.98, 0.0, 1.0);
    }
    claim.finish();
    claims.push_back(out);
  }
  return claims;
}

std::vector<std::pair<std::string, std::string>> read_tradeoffs(const ConfigNode& root,
                                                                const std::vector<std::string>& metrics,
                                                                const std::string& primary_metric) {
  std::optional<ConfigNode> list = root.optional_child("tradeoffs");
  if (!list) return {{"frame_ms", primary_metric}};
  if (!list->is_sequence() || list->size() == 0)
    root.fail("tradeoffs", "a non-empty list of [x, y] pairs such as [[frame_ms, relmse], [memory_bytes, relmse]]",
              list->describe_value());
  std::vector<std::pair<std::string, std::string>> pairs;
  for (size_t i = 0; i < list->size(); ++i) {
    ConfigNode pair = list->at(i);
    if (!pair.is_sequence() || pair.size() != 2)
      pair.fail_here("an [x, y] pair of quantities such as [frame_ms, relmse]", pair.describe_value());
    std::string x = read_quantity(pair.at(0), "", metrics, true), y = read_quantity(pair.at(1), "", metrics, true);
    if (x == y) pair.fail_here("two different quantities", "'" + x + "' twice");
    if (std::find(pairs.begin(), pairs.end(), std::pair{x, y}) != pairs.end())
      pair.fail_here("each trade-off once", fmt::format("[{}, {}] again", x, y));
    pairs.push_back({x, y});
  }
  return pairs;
}

}  // namespace

nlohmann::json ReportSettings::tradeoffs_json() const {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [x, y] : tradeoffs) out.push_back({x, y});
  return out;
}

ReportSettings read_report_settings(const ConfigNode& root, const std::vector<std::string>& metrics,
                                    const std::string& primary_metric, const std::vector<std::string>& variants) {
  ReportSettings settings;
  if (std::optional<ConfigNode> paper = root.optional_child("paper")) settings.paper = read_paper(*paper, variants);
  if (std::optional<ConfigNode> claims = root.optional_child("claims")) settings.claims = read_claims(*claims, metrics);
  settings.tradeoffs = read_tradeoffs(root, metrics, primary_metric);
  settings.budgets_ms = read_increasing(root, "budgets_ms", kDefaultBudgetsMs, 1e9);
  settings.total_cost_frames = read_increasing(root, "total_cost_frames", kDefaultTotalCostFrames, 1e12);
  settings.case_table = root.boolean_or("case_table", false);
  if (root.has("error_targets")) {
    // Targets of the primary metric: any finite numbers, listed from the loosest to the strictest is
    // not required (the metric's direction decides which is stricter), but each once.
    ConfigNode list = root.child("error_targets");
    if (!list.is_sequence() || list.size() == 0) root.fail("error_targets", "a non-empty list of numbers", list.describe_value());
    for (size_t i = 0; i < list.size(); ++i) {
      ConfigNode entry = list.at(i);
      double value = entry.as_number();
      if (!std::isfinite(value)) entry.fail_here("a finite number", entry.describe_value());
      if (std::count(settings.error_targets.begin(), settings.error_targets.end(), value))
        entry.fail_here("each target once", entry.describe_value());
      settings.error_targets.push_back(value);
    }
  }
  return settings;
}

}  // namespace causticbench
