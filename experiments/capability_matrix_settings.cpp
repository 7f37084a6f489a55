// The experiment's `capability_matrix` key (declared in capability_matrix_settings.h).
#include "experiments/capability_matrix_settings.h"

#include <algorithm>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/config.h"
#include "core/errors.h"
#include "experiments/experiment.h"
#include "methods/registry.h"

namespace causticbench {

namespace {

std::vector<std::string> capability_names() {
  std::vector<std::string> names;
  for (const auto& [name, value] : Capabilities{}.entries()) names.push_back(name);
  return names;
}

// A capability named by `node` (a scalar): one of Capabilities::entries().
std::string read_capability(const ConfigNode& node) {
  const std::string name = node.as_string();
  const std::vector<std::string> names = capability_names();
  if (std::find(names.begin(), names.end(), name) == names.end())
    node.fail_here("a capability (" + join(names, ", ") + ")", "'" + name + "'" + did_you_mean(name, names));
  return name;
}

std::vector<std::string> experiment_methods(const Experiment& experiment) {
  std::vector<std::string> methods;
  for (const RunSpec& run : experiment.runs)
    if (std::find(methods.begin(), methods.end(), run.method) == methods.end()) methods.push_back(run.method);
  return methods;
}

// `select: {method: filter}`: a method of the experiment and a --filter that can match its runs.
nlohmann::json read_select(const ConfigNode& node, const Experiment& experiment) {
  nlohmann::json select = nlohmann::json::object();
  if (!node.is_map()) node.fail_here("a map from method to a run filter, such as {pinhole: interaction=reflect}",
                                     node.describe_value());
  const std::vector<std::string> methods = experiment_methods(experiment);
  for (const std::string& method : node.keys()) {
    if (std::find(methods.begin(), methods.end(), method) == methods.end())
      node.fail(method, "a method of the experiment (" + join(methods, ", ") + ")",
                "'" + method + "'" + did_you_mean(method, methods));
    const std::string filter = node.string(method);
    try {
      check_filter_terms(experiment, filter);
    } catch (const InputError& error) {
      throw InputError(fmt::format("{}: {}", node.location_of(method).describe(), error.what()));
    }
    select[method] = filter;
  }
  return select;
}

nlohmann::json read_published(const ConfigNode& node) {
  nlohmann::json published = {{"title", node.string("title")}, {"rows", nlohmann::json::object()},
                              {"methods", nlohmann::json::object()}};
  ConfigNode rows = node.child("rows");
  if (!rows.is_map()) rows.fail_here("a map from capability to the table's row names", rows.describe_value());
  for (const std::string& key : rows.keys()) {
    ConfigNode names = rows.child(key);
    const std::vector<std::string> known = capability_names();
    if (std::find(known.begin(), known.end(), key) == known.end())
      rows.fail(key, "a capability (" + join(known, ", ") + ")", "'" + key + "'" + did_you_mean(key, known));
    if (!names.is_sequence() || names.size() == 0)
      names.fail_here("a non-empty list of the table's row names", names.describe_value());
    for (size_t i = 0; i < names.size(); ++i) published["rows"][key].push_back(names.at(i).as_string());
  }
  ConfigNode methods = node.child("methods");
  if (!methods.is_map()) methods.fail_here("a map from method to the capabilities the table marks", methods.describe_value());
  for (const std::string& method : methods.keys()) {
    try {
      find_method(method);  // a column for an unknown method is a typo
    } catch (const InputError& error) {
      throw InputError(fmt::format("{}: {}", methods.location_of(method).describe(), error.what()));
    }
    ConfigNode marked = methods.child(method);
    if (!marked.is_sequence()) marked.fail_here("a list of capabilities (empty: none marked)", marked.describe_value());
    published["methods"][method] = nlohmann::json::array();
    for (size_t i = 0; i < marked.size(); ++i) {
      std::string capability = read_capability(marked.at(i));
      // A mark in a row the table does not have contradicts `rows`.
      if (!published["rows"].contains(capability))
        marked.at(i).fail_here("a capability that `rows` maps to a row of the table", "'" + capability + "'");
      if (std::count(published["methods"][method].begin(), published["methods"][method].end(), capability))
        marked.at(i).fail_here("each capability once", "'" + capability + "' again");
      published["methods"][method].push_back(capability);
    }
  }
  node.finish();
  return published;
}

// The runs of `method` on variant `variant` that `filter` selects (all of them when it is empty).
size_t selected_runs(const Experiment& experiment, const std::string& method, const std::string& variant,
                     const std::string& filter) {
  size_t count = 0;
  for (const RunSpec& run : experiment.runs) {
    if (run.method != method || experiment.variants[run.variant].name != variant) continue;
    if (filter.empty() || run_matches_filter(experiment, run, filter)) ++count;
  }
  return count;
}

}  // namespace

nlohmann::json read_capability_matrix(const ConfigNode& node, const Experiment& experiment) {
  if (!node.is_map()) node.fail_here("a map with cases (and published, select)", node.describe_value());
  // The verdict rule (capability_verdict.h) judges by both.
  for (const char* metric : {"relmse", "energy_ratio"}) {
    if (std::find(experiment.metrics.begin(), experiment.metrics.end(), metric) == experiment.metrics.end())
      node.fail_here(fmt::format("an experiment whose metrics include relmse and energy_ratio (the capability verdict "
                                 "judges by both)"),
                     fmt::format("metrics without {}", metric));
  }
  nlohmann::json matrix = {{"published", nullptr}, {"select", nlohmann::json::object()}, {"cases", nlohmann::json::array()}};
  if (std::optional<ConfigNode> published = node.optional_child("published")) matrix["published"] = read_published(*published);
  if (std::optional<ConfigNode> select = node.optional_child("select")) matrix["select"] = read_select(*select, experiment);

  // The frame every case is judged by: by default the experiment's last, the one furthest into a moving
  // case's animation (its earlier frames are played, so that prepare() and update() see the motion).
  matrix["frame"] = experiment.frames.back();
  if (node.has("frame")) {
    const int frame = node.integer("frame", 0, 1 << 30);
    if (std::find(experiment.frames.begin(), experiment.frames.end(), frame) == experiment.frames.end())
      node.fail("frame", fmt::format("one of the experiment's frames ({})", fmt::join(experiment.frames, ", ")),
                std::to_string(frame));
    matrix["frame"] = frame;
  }

  std::vector<std::string> variants;
  for (const SceneVariant& variant : experiment.variants) variants.push_back(variant.name);
  ConfigNode cases = node.child("cases");
  if (!cases.is_sequence() || cases.size() == 0) cases.fail_here("a non-empty list of cases", cases.describe_value());
  std::set<std::string> seen;
  for (size_t i = 0; i < cases.size(); ++i) {
    ConfigNode entry = cases.at(i);
    nlohmann::json out;
    out["capability"] = read_capability(entry.child("capability"));
    if (!seen.insert(out["capability"].get<std::string>()).second)
      entry.fail("capability", "each capability in one case", "'" + out["capability"].get<std::string>() + "' again");
    for (const char* key : {"with", "without"}) {
      std::string name = entry.string(key);
      if (std::find(variants.begin(), variants.end(), name) == variants.end())
        entry.fail(key, "a variant of the experiment (" + join(variants, ", ") + ")",
                   "'" + name + "'" + did_you_mean(name, variants));
      out[key] = name;
    }
    if (out["with"] == out["without"]) entry.fail("without", "a variant other than `with`", "the same variant");
    out["built_on"] = entry.has("built_on") ? read_capability(entry.child("built_on")) : "";
    out["select"] = nlohmann::json::object();
    if (std::optional<ConfigNode> select = entry.optional_child("select")) out["select"] = read_select(*select, experiment);
    entry.finish();
    // Each method must have exactly one run to judge on each of the case's variants.
    for (const std::string& method : experiment_methods(experiment)) {
      std::string filter = out["select"].value(method, matrix["select"].value(method, std::string()));
      for (const char* key : {"with", "without"}) {
        size_t count = selected_runs(experiment, method, out[key].get<std::string>(), filter);
        if (count != 1)
          entry.fail(key, fmt::format("one run of {} on the variant to judge (set `select: {{{}: FILTER}}`)", method, method),
                     fmt::format("{} runs{}", count, filter.empty() ? "" : " matching '" + filter + "'"));
      }
    }
    matrix["cases"].push_back(out);
  }
  node.finish();

  // The declarations as the code makes them now (`causticbench list`).
  matrix["declared"] = nlohmann::json::object();
  for (const std::string& method : experiment_methods(experiment)) {
    const MethodInfo& info = find_method(method).info();
    nlohmann::json declared = {{"capabilities", nlohmann::json::object()}, {"notes", nlohmann::json::object()}};
    for (const auto& [name, value] : info.capabilities.entries()) declared["capabilities"][name] = value;
    for (const auto& [name, note] : info.capabilities.notes) declared["notes"][name] = note;
    matrix["declared"][method] = declared;
  }
  return matrix;
}

}  // namespace causticbench
