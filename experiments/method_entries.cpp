#include "experiments/method_entries.h"

#include <algorithm>
#include <optional>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/hash.h"
#include "methods/plugins.h"
#include "methods/registry.h"

namespace causticbench {

using SweepLists = std::vector<std::pair<std::string, std::vector<ParamDict::Entry>>>;

std::vector<KnobAssignment> expand_sweep(const KnobAssignment& fixed, const SweepLists& sweep, const SweepLists& zip) {
  std::vector<KnobAssignment> result;
  size_t zip_length = zip.empty() ? 1 : zip.front().second.size();
  for (size_t i = 0; i < zip_length; ++i) {
    KnobAssignment base = fixed;
    for (const auto& [name, values] : zip) base[name] = values[i];
    result.push_back(base);
  }
  for (const auto& [name, values] : sweep) {
    std::vector<KnobAssignment> product;
    for (const KnobAssignment& partial : result) {
      for (const ParamDict::Entry& value : values) {
        KnobAssignment next = partial;
        next[name] = value;
        product.push_back(next);
      }
    }
    result = std::move(product);
  }
  return result;
}

namespace {

SweepLists read_lists(const ConfigNode& node) {
  SweepLists lists;
  for (const std::string& key : node.keys()) {
    ConfigNode list = node.child(key);
    if (!list.is_sequence() || list.size() == 0) list.fail_here("a non-empty list of values", list.describe_value());
    std::vector<ParamDict::Entry> values;
    for (size_t i = 0; i < list.size(); ++i) {
      ConfigNode item = list.at(i);
      values.push_back(ParamDict::Entry{item.as_string(), item.location()});
    }
    lists.push_back({key, values});
  }
  return lists;
}

void read_fixed(const ConfigNode& node, KnobAssignment& fixed, const MethodInfo& info, const ParamPhase* phase) {
  for (const std::string& key : node.keys()) {
    ConfigNode value = node.child(key);
    if (phase) {
      if (const ParamSpec* spec = find_param_spec(info.params, key)) {
        if (spec->phase != *phase) {
          value.fail_here(fmt::format("a {} knob of '{}' here ('{}' is a {} knob: put it under `{}:` or `knobs:`)",
                                      phase_name(*phase), info.name, key, phase_name(spec->phase), phase_name(spec->phase)),
                          value.describe_value());
        }
      }
    }
    if (fixed.count(key)) value.fail_here("each knob given once per method entry", "'" + key + "' again");
    fixed[key] = ParamDict::Entry{value.as_string(), value.location()};
  }
}

// An entry's knobs as written: fixed under build:, frame:, render: or knobs:, and varied by sweep: or zip:.
struct EntryKnobs {
  KnobAssignment fixed;
  SweepLists sweep, zip;
  std::set<std::string> varied;  // the knobs of sweep and zip
};

EntryKnobs read_entry_knobs(const ConfigNode& entry, const MethodInfo& info) {
  EntryKnobs knobs;
  for (ParamPhase phase : {ParamPhase::build, ParamPhase::frame, ParamPhase::render}) {
    if (std::optional<ConfigNode> node = entry.optional_child(phase_name(phase))) read_fixed(*node, knobs.fixed, info, &phase);
  }
  if (std::optional<ConfigNode> node = entry.optional_child("knobs")) read_fixed(*node, knobs.fixed, info, nullptr);
  if (std::optional<ConfigNode> node = entry.optional_child("sweep")) knobs.sweep = read_lists(*node);
  if (std::optional<ConfigNode> node = entry.optional_child("zip")) {
    knobs.zip = read_lists(*node);
    const auto& [first_name, first_values] = knobs.zip.front();
    for (const auto& [name, values] : knobs.zip) {
      if (values.size() != first_values.size()) {
        node->fail(name, fmt::format("a list of {} values, as long as '{}'", first_values.size(), first_name),
                   fmt::format("{} values", values.size()));
      }
    }
  }
  for (const auto& list : {knobs.sweep, knobs.zip}) {
    for (const auto& [name, values] : list) {
      if (knobs.fixed.count(name) || knobs.varied.count(name)) {
        throw_input_error(values.front().where, name, "each knob either fixed or swept, once", "it twice");
      }
      knobs.varied.insert(name);
    }
  }
  return knobs;
}

// `variants`: the entry runs only on the variants it names (a per-object setting in an experiment whose
// variants are different objects), every variant without it.
std::vector<bool> entry_variants(const ConfigNode& entry, const Experiment& experiment) {
  std::vector<bool> on_variant(experiment.variants.size(), true);
  std::optional<ConfigNode> node = entry.optional_child("variants");
  if (!node) return on_variant;
  const std::vector<std::string> names = experiment.variant_names();
  if (!node->is_sequence() || node->size() == 0) node->fail_here("a non-empty list of variant names", node->describe_value());
  on_variant.assign(experiment.variants.size(), false);
  for (size_t i = 0; i < node->size(); ++i) {
    ConfigNode item = node->at(i);
    const std::string name = item.as_string();
    const auto found = std::find(names.begin(), names.end(), name);
    if (found == names.end()) {
      item.fail_here(fmt::format("the name of one of the experiment's variants ({}){}", join(names, ", "),
                                 did_you_mean(name, names)),
                     "'" + name + "'");
    }
    const size_t index = static_cast<size_t>(found - names.begin());
    if (on_variant[index]) item.fail_here("each variant once", "'" + name + "' again");
    on_variant[index] = true;
  }
  return on_variant;
}

// Adds the entry's runs to the count, refusing the experiment when it passes max_runs.
void count_runs(const ConfigNode& entry, const EntryKnobs& knobs, size_t variants, RunCount& count) {
  const size_t zipped = knobs.zip.empty() ? 1 : knobs.zip.front().second.size();
  double entry_runs = static_cast<double>(zipped) * static_cast<double>(variants);
  std::string product = fmt::format("{}", zipped);
  for (const auto& [name, values] : knobs.sweep) {
    entry_runs *= static_cast<double>(values.size());
    product += fmt::format(" x {} ({})", values.size(), name);
  }
  count.counted += entry_runs;
  if (count.counted > static_cast<double>(count.max_runs)) {
    throw_input_error(entry.has("sweep") ? entry.location_of("sweep") : entry.location(), entry.path(),
                      fmt::format("at most max_runs = {} runs in the experiment (set `max_runs`, up to {}, to allow "
                                  "more)", count.max_runs, kLargestMaximumRuns),
                      fmt::format("{:.0f} runs up to this entry, {:.0f} of them here: {}{}", count.counted, entry_runs,
                                  product, variants > 1 ? fmt::format(" x {} variants", variants) : ""));
  }
}

// Every combination of the entry's knobs, resolved and split by phase, with the text of its swept
// values for the label. The knobs do not depend on the variant: resolved once, run on every variant.
std::vector<std::pair<RunSpec, std::string>> resolve_combinations(const ConfigNode& entry, const MethodInfo& info,
                                                                  const EntryKnobs& entry_knobs) {
  std::vector<std::pair<RunSpec, std::string>> resolved;  // knobs, swept text
  std::set<std::string> applied;  // swept knobs that apply in at least one combination
  for (const KnobAssignment& assignment : expand_sweep(entry_knobs.fixed, entry_knobs.sweep, entry_knobs.zip)) {
    ParamDict dict;
    for (const auto& [name, value] : assignment) dict.set(name, value.text, value.where);
    RunSpec knobs;
    knobs.method = info.name;
    // A swept knob that does not apply to this combination (sh_order under storage: grid) is
    // dropped, so the combinations it would multiply collapse into one run (same key, kept once).
    knobs.params = dict.resolve(info.params, info.name, entry_knobs.varied);
    if (std::optional<BrokenKnobRule> broken = broken_knob_rule(info, knobs.params)) {
      // Blamed on the first of its knobs this entry sets (a default breaks no rule on its own).
      SourceLocation where = entry.location();
      std::string key = entry.path();
      for (const std::string& knob : broken->rule->knobs) {
        auto set = assignment.find(knob);
        if (set == assignment.end()) continue;
        where = set->second.where;
        key = entry.path() + "." + knob;
        break;
      }
      throw_input_error(where, key, "knobs that agree with each other", broken->describe(info.name));
    }
    knobs.build = select_phase(knobs.params, info.params, ParamPhase::build);
    knobs.frame = select_phase(knobs.params, info.params, ParamPhase::frame);
    knobs.render = select_phase(knobs.params, info.params, ParamPhase::render);
    std::string swept_text;
    for (const std::string& name : entry_knobs.varied) {
      if (!knobs.params.has(name)) continue;
      applied.insert(name);
      knobs.swept[name] = format_param_value(knobs.params.values().at(name));
      swept_text += fmt::format(" {}={}", name, knobs.swept[name]);
    }
    resolved.emplace_back(std::move(knobs), swept_text);
  }
  for (const auto& list : {entry_knobs.sweep, entry_knobs.zip}) {
    for (const auto& [name, values] : list) {
      if (applied.count(name)) continue;
      const ParamSpec* spec = find_param_spec(info.params, name);
      throw_input_error(values.front().where, info.name + "." + name,
                        fmt::format("a knob that applies to at least one run of the sweep ({})",
                                    spec ? spec->condition_text() : "?"),
                        "it applies to none");
    }
  }
  return resolved;
}

}  // namespace

void add_method_entry(const ConfigNode& entry, Experiment& experiment, RunCount& count) {
  std::string method_name = entry.string("method");
  const MethodEntry* method;
  try {
    method = &find_method(method_name);
  } catch (const InputError& error) {
    throw InputError(fmt::format("{}: {}", entry.location_of("method").describe(), error.what()));
  }
  const MethodInfo& info = method->info();
  const std::string label = entry.string_or("label", info.name);
  const EntryKnobs knobs = read_entry_knobs(entry, info);
  const std::vector<bool> on_variant = entry_variants(entry, experiment);
  entry.finish();
  count_runs(entry, knobs, static_cast<size_t>(std::count(on_variant.begin(), on_variant.end(), true)), count);
  const std::vector<std::pair<RunSpec, std::string>> resolved = resolve_combinations(entry, info, knobs);
  for (size_t v = 0; v < experiment.variants.size(); ++v) {
    if (!on_variant[v]) continue;
    const SceneVariant& variant = experiment.variants[v];
    for (const auto& [run_knobs, swept_text] : resolved) {
      RunSpec run = run_knobs;
      run.variant = v;
      run.entry = label;
      run.label = label + swept_text + (experiment.variants.size() > 1 ? " @" + variant.name : "");
      run.spec = {{"scene_hash", variant.scene_hash}, {"overrides", variant.overrides},
                  {"frames", experiment.frames},         {"repetitions", experiment.repetitions},
                  {"method", info.name},                 {"params", run.params.key_json(info.params)}};
      // Only when not 1, so that runs stored before the option keep their keys.
      if (experiment.pixel_samples != 1) run.spec["pixel_samples"] = experiment.pixel_samples;
      // A plugin's method: which build of the plugin (a rebuilt plugin is measured again).
      if (method->plugin) run.spec["plugin"] = method->plugin->key_json();
      run.key = hash_json(run.spec);
      if (!count.keys.insert(run.key).second) continue;  // the same run twice: keep one
      experiment.runs.push_back(std::move(run));
    }
  }
}

}  // namespace causticbench
