// Loading the stored results into the report model (docs/results-format.md): experiment.json,
// environment.json, every run's record.json (checked by the store's own check, a damaged one shown as
// failed), the metric columns, the scene variants, which variant and reference each run belongs to, and
// each variant's reference record. What is missing becomes a note at the top of the report, not an error.
#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <set>

#include "core/errors.h"
#include "store/record_check.h"
#include "store/result_paths.h"
#include "experiments/report_settings.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

namespace {

// Why a run is stale: the reference it was measured against and the experiment's current one, with the
// settings that differ when the record names its reference's (version 2 records do).
std::string stale_reason(const Run& run, const Variant& variant, const json& current_settings) {
  std::string differences;
  const json& then = run.record.reference_settings;
  if (then.is_object() && current_settings.is_object()) {
    std::vector<std::string> changed;
    std::set<std::string> names;
    for (const auto& [name, value] : then.items()) names.insert(name);
    for (const auto& [name, value] : current_settings.items()) names.insert(name);
    for (const std::string& name : names) {
      const json& before = member(then, name);
      const json& now = member(current_settings, name);
      if (before != now)
        changed.push_back(fmt::format("{} {} → {}", name, before.is_null() ? "unset" : before.dump(),
                                      now.is_null() ? "unset" : now.dump()));
    }
    differences = changed.empty() ? "; the reference settings are the same, so the scene or its variant changed"
                                  : "; reference settings changed: " + join(changed, ", ");
  }
  return fmt::format("stale: measured against reference {}, but the experiment's reference is now {}{}",
                     run.reference_key.substr(0, 12), variant.reference_key.substr(0, 12), differences);
}

// A list of numbers of experiment.json, or `fallback` when it has none (written before the key).
std::vector<double> numbers_or(const json& experiment, const char* key, const std::vector<double>& fallback) {
  const json& list = member(experiment, key);
  if (!list.is_array()) return fallback;
  std::vector<double> values;
  for (const json& value : list)
    if (value.is_number()) values.push_back(value.get<double>());
  return values;
}

// The trade-offs, budgets, error targets and frame counts the experiment compares (experiments/
// report_settings.h). A trade-off naming a quantity the registry does not know (a hand-edited or newer
// experiment.json) is left out with a note that names the closest known one.
void read_comparisons(Report& report) {
  const json& listed = member(report.experiment, "tradeoffs");
  if (listed.is_array()) {
    for (const json& pair : listed) {
      if (!pair.is_array() || pair.size() != 2 || !pair[0].is_string() || !pair[1].is_string()) {
        report.notes.push_back("experiment.json has a trade-off that is not an [x, y] pair of names: " + pair.dump());
        continue;
      }
      Tradeoff tradeoff{pair[0].get<std::string>(), pair[1].get<std::string>(), {}};
      bool known = true;
      for (const std::string& name : {tradeoff.x, tradeoff.y}) {
        if (find_quantity(name)) continue;
        report.notes.push_back(fmt::format("The trade-off [{}, {}] is not drawn: '{}' is not {}.", tradeoff.x,
                                           tradeoff.y, name, expected_quantity_text(name, true)));
        known = false;
      }
      if (known) report.tradeoffs.push_back(tradeoff);
    }
  } else {
    report.tradeoffs.push_back({"frame_ms", report.primary, {}});
  }
  report.budgets_ms = numbers_or(report.experiment, "budgets_ms", kDefaultBudgetsMs);
  report.error_targets = numbers_or(report.experiment, "error_targets", {});
  report.total_cost_frames = numbers_or(report.experiment, "total_cost_frames", kDefaultTotalCostFrames);
}

}  // namespace

void load_report(Report& report, const std::string& folder_text) {
  if (folder_text.empty()) throw InputError("report: no experiment folder given (expected results/<experiment>/)");
  fs::path folder(folder_text);
  std::error_code error;
  if (!fs::exists(folder, error)) {
    throw InputError(
        fmt::format("'{}' does not exist: expected an experiment results folder such as "
                    "results/<experiment>/, written by `causticbench run EXPERIMENT.yaml`",
                    folder_text));
  }
  if (!fs::is_directory(folder, error)) {
    throw InputError(
        fmt::format("'{}' is a file, not an experiment results folder (results/<experiment>/)", folder_text));
  }
  folder = fs::absolute(folder).lexically_normal();
  if (folder.filename().empty()) folder = folder.parent_path();
  report.folder = folder;
  if (!fs::is_regular_file(folder / "experiment.json")) {
    throw InputError(fmt::format("'{}' is not an experiment results folder: it has no experiment.json{}", folder_text,
                                 experiment_folders_hint(folder_text)));
  }
  report.experiment = read_json(folder / "experiment.json");
  if (!report.experiment.is_object())
    throw InputError(fmt::format("{} is not a JSON object", (folder / "experiment.json").string()));
  report.name = string_member(report.experiment, "name", folder.filename().string());

  if (fs::is_regular_file(folder / "environment.json")) {
    report.environment = read_json(folder / "environment.json");
  } else {
    report.notes.push_back("environment.json is missing: the machine these numbers come from is unknown.");
  }

  // Runs: the experiment's list, in its order; without a list, every runs/<key>/ folder.
  std::vector<std::string> keys;
  const json& listed = member(report.experiment, "runs");
  if (listed.is_array()) {
    for (const json& key : listed)
      if (key.is_string()) keys.push_back(key.get<std::string>());
  } else if (fs::is_directory(folder / "runs")) {
    for (const auto& entry : fs::directory_iterator(folder / "runs"))
      if (entry.is_directory()) keys.push_back(entry.path().filename().string());
    std::sort(keys.begin(), keys.end());
  }
  size_t unconverged = 0;  // runs measured against a reference stopped by its time cap
  for (const std::string& key : keys) {
    fs::path path = folder / "runs" / key / "record.json";
    if (!fs::is_regular_file(path)) {
      report.missing.push_back(key);
      continue;
    }
    Run run;
    run.key = key;
    try {
      json stored = read_json(path);
      // The store's own check (store/record_check.h): a damaged record is never shown as ok.
      std::string problem = run_record_problem(stored, (folder / "runs" / key).string());
      if (!problem.empty()) throw InputError(fmt::format("damaged record {}: {}", path.string(), problem));
      run.record = RunRecord::from_json(stored);
    } catch (const std::exception& failure) {
      run.record = RunRecord{};
      run.record.key = key;
      run.record.status = "failed";
      run.record.error = failure.what();
    }
    run.status = run.record.status;
    run.ok = run.record.ok();
    run.method = run.record.method.empty() ? "?" : run.record.method;
    run.label = run.record.label.empty() ? run.method + " " + key.substr(0, 8) : run.record.label;
    run.entry = run.record.entry.empty() ? run.method : run.record.entry;
    run.changed = knobs_changed_from_defaults(run.record);
    run.error = run.record.error;
    if (!run.ok && run.error.empty()) run.error = "(no error message recorded)";
    run.empty_reference = run.record.empty_reference_frames.has_value();
    if (run.record.reference_converged == false) ++unconverged;
    report.runs.push_back(std::move(run));
  }
  if (unconverged)
    report.notes.push_back(fmt::format("{} run(s) were measured against a reference that stopped on its time cap "
                                       "(max_seconds), not converged: their errors include the reference's own.",
                                       unconverged));
  if (report.runs.empty() && report.missing.empty()) report.notes.push_back("experiment.json names no runs.");
  if (fs::is_directory(folder / "runs")) {
    std::set<std::string> known(keys.begin(), keys.end());
    size_t stale = 0;
    for (const auto& entry : fs::directory_iterator(folder / "runs"))
      if (entry.is_directory() && !known.count(entry.path().filename().string())) ++stale;
    if (stale)
      report.notes.push_back(
          fmt::format("{} folder(s) under runs/ are not runs of this experiment (an earlier "
                      "version of it?) and are left out.",
                      stale));
  }

  for (const Run& run : report.runs) {
    if (std::find(report.methods.begin(), report.methods.end(), run.method) == report.methods.end())
      report.methods.push_back(run.method);
    if (std::find(report.entries.begin(), report.entries.end(), run.entry) == report.entries.end())
      report.entries.push_back(run.entry);
  }

  // Metric columns: the experiment's, then any other metric a run stored (temporal_flicker, ...),
  // except nonfinite_pixels unless some run has any.
  const json& named = member(report.experiment, "metrics");
  if (named.is_array()) {
    for (const json& metric : named)
      if (metric.is_string()) report.metrics.push_back(metric.get<std::string>());
  }
  std::set<std::string> stored;
  bool nonfinite = false;
  for (const Run& run : report.runs) {
    for (const auto& [name, why] : run.record.metrics_undefined) stored.insert(name);
    for (const auto& [name, value] : run.record.metrics) {
      stored.insert(name);
      if (name == "nonfinite_pixels" && value > 0) nonfinite = true;
    }
  }
  std::vector<std::string> extra;
  for (const MetricInfo& info : metric_registry())
    if (stored.count(info.name)) extra.push_back(info.name);
  for (const std::string& name : stored)
    if (!metric_info(name)) extra.push_back(name);
  for (const std::string& name : extra) {
    if (name == "nonfinite_pixels" && !nonfinite) continue;
    if (std::find(report.metrics.begin(), report.metrics.end(), name) == report.metrics.end())
      report.metrics.push_back(name);
  }
  report.primary = string_member(report.experiment, "primary_metric");
  if (report.primary.empty()) {
    report.primary = std::find(report.metrics.begin(), report.metrics.end(), "relmse") != report.metrics.end()
                         ? "relmse"
                         : (report.metrics.empty() ? "relmse" : report.metrics.front());
  }

  read_comparisons(report);
  // Several seeds asked for (an older experiment.json has no "seeds"), or some record measured with several.
  const json& seeds = member(report.experiment, "seeds");
  report.seeds = seeds.is_number_integer() ? std::max(1, seeds.get<int>()) : 1;
  for (const Run& run : report.runs) report.seeds = std::max(report.seeds, run.record.seed_count());

  // The scene variants: experiment.json's list; without one, a single "default" variant with the
  // top-level reference_key.
  std::string top_key = string_member(report.experiment, "reference_key");
  const json& listed_variants = member(report.experiment, "variants");
  if (listed_variants.is_array()) {
    for (const json& entry : listed_variants) {
      if (!entry.is_object()) continue;
      Variant variant;
      variant.name = string_member(
          entry, "name", report.variants.empty() ? "default" : fmt::format("variant{}", report.variants.size()));
      variant.reference_key = string_member(entry, "reference_key", report.variants.empty() ? top_key : "");
      variant.resolution = member(entry, "resolution");
      variant.overrides = member(entry, "overrides");
      bool known = std::any_of(report.variants.begin(), report.variants.end(),
                               [&](const Variant& v) { return v.name == variant.name; });
      if (!known) report.variants.push_back(std::move(variant));
    }
  }
  if (report.variants.empty()) {
    Variant variant;
    variant.name = "default";
    variant.reference_key = top_key;
    variant.resolution = member(report.experiment, "resolution");
    variant.overrides = member(report.experiment, "overrides");
    report.variants.push_back(std::move(variant));
  }
  std::vector<std::string> unlisted;
  for (Run& run : report.runs) {
    run.variant = run.record.variant;
    run.reference_key = run.record.reference_key;
    if (run.variant.empty()) {
      auto named = std::find_if(report.variants.begin(), report.variants.end(), [&](const Variant& v) {
        return !run.reference_key.empty() && v.reference_key == run.reference_key;
      });
      run.variant = named != report.variants.end() ? named->name : report.variants.front().name;
    }
    auto found = std::find_if(report.variants.begin(), report.variants.end(),
                              [&](const Variant& v) { return v.name == run.variant; });
    if (found == report.variants.end()) {
      Variant variant;
      variant.name = run.variant;
      variant.reference_key = run.reference_key;
      variant.listed = false;
      unlisted.push_back(run.variant);
      report.variants.push_back(std::move(variant));
      found = std::prev(report.variants.end());
    }
    run.variant_index = static_cast<size_t>(found - report.variants.begin());
    if (run.reference_key.empty()) run.reference_key = found->reference_key;
    if (run.ok && found->listed && !found->reference_key.empty() && run.reference_key != found->reference_key) {
      run.stale = true;
      run.ok = false;
      run.status = "stale";
      run.error = stale_reason(run, *found, member(report.experiment, "reference"));
    }
  }
  if (size_t stale = report.stale_count())
    report.notes.push_back(fmt::format(
        "{} run(s) were measured against another reference than the experiment's current one (its settings or "
        "scene changed since): they are stale, listed with the runs not compared, and left out of every front, "
        "claim and view. `causticbench run` measures them again.",
        stale));
  if (!unlisted.empty())
    report.notes.push_back(
        fmt::format("Run records name variant(s) that experiment.json does not list: {}.", join(unlisted, ", ")));

  // Each variant's reference record: reference error, history, passes, seconds.
  std::map<std::string, json> records;
  std::set<std::string> missing_records;
  for (Variant& variant : report.variants) {
    if (variant.reference_key.empty()) {
      report.notes.push_back(report.multi() ? fmt::format("Variant {} names no reference_key: no reference image, "
                                                          "reference error or error maps for it.",
                                                          variant.name)
                                            : "experiment.json names no reference_key: no reference images, noise "
                                              "floor or error maps.");
      continue;
    }
    fs::path path = report.reference_folder(variant.reference_key) / "record.json";
    if (!records.count(variant.reference_key)) {
      if (fs::is_regular_file(path)) {
        records[variant.reference_key] = read_json(path);
      } else {
        records[variant.reference_key] = nullptr;
        if (missing_records.insert(variant.reference_key).second)
          report.notes.push_back(fmt::format("The reference record {} is missing: no reference error or convergence plot{}.",
                                             path.string(), report.multi() ? " for variant " + variant.name : ""));
      }
    }
    variant.reference = records[variant.reference_key];
    const json& floor = member(variant.reference, "error_estimate");
    if (floor.is_number()) variant.reference_error = floor.get<double>();
    const json& history = member(variant.reference, "history");
    if (history.is_array()) variant.history = history;
  }

  // Where each compared run's light went, once: the findings, the results table, results.json and the
  // study's summary read it.
  for (Run& run : report.runs) {
    if (!run.ok || run.empty_reference) continue;
    const json& reference = report.variants.at(run.variant_index).reference;
    run.light_account = account_for_record(reference, run.record);
    if (run.light_account) run.frame_light_accounts = frame_accounts(reference, run.record);
  }
}

}  // namespace causticbench::report_detail
