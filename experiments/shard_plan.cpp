#include "experiments/shard_plan.h"

#include <algorithm>
#include <numeric>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "experiments/seed_replicas.h"
#include "store/run_folders.h"
#include "store/store_files.h"

namespace causticbench {

namespace {

// The model's cost of a run in arbitrary units: every pixel of every frame, each timed pass and the warm-up.
double model_units(const Experiment& experiment, const RunSpec& run) {
  const Camera& camera = experiment.variants.at(run.variant).scene.camera;
  return static_cast<double>(camera.width) * camera.height * static_cast<double>(experiment.frames.size()) *
         (experiment.repetitions + 1) * seed_count(experiment, run);
}

struct StoredCost {
  bool stored = false;           // ok or failed: the shards will skip it
  bool timed = false;            // an ok record with timings
  double run_seconds = 0.0;      // update and render over every pass, the warm-up counted as one more
  double uncached_prepare = 0.0;  // prepare() seconds when its build is not cached (each shard prepares again)
};

StoredCost stored_cost(const ResultPaths& paths, const Experiment& experiment, const RunSpec& run) {
  StoredCost cost;
  StoredRun stored = inspect_stored_run(paths.run(experiment.name, run.key));
  cost.stored = stored.state == StoredRun::State::stored;
  const nlohmann::json& record = stored.record;
  if (!cost.stored || record.value("status", "") != "ok" || !record.contains("frames") || !record["frames"].is_array()) {
    return cost;
  }
  for (const nlohmann::json& frame : record["frames"]) {
    for (const char* field : {"update_ms", "render_ms"}) {
      if (!frame.contains(field) || !frame[field].is_array() || frame[field].empty()) continue;
      double sum = 0.0;
      for (const nlohmann::json& value : frame[field]) sum += value.is_number() ? value.get<double>() : 0.0;
      cost.run_seconds += sum / 1000.0 * (1.0 + 1.0 / static_cast<double>(frame[field].size()));
      cost.timed = true;
    }
  }
  // Its frames' timings are its first seed's: each of its seeds took about as long.
  if (record.contains("seeds") && record["seeds"].is_object() && record["seeds"].value("runs", nlohmann::json()).is_array())
    cost.run_seconds *= static_cast<double>(std::max<size_t>(1, record["seeds"]["runs"].size()));
  if (record.contains("prepare") && record["prepare"].is_object() && record["prepare"].value("build_key", "").empty()) {
    cost.uncached_prepare = record["prepare"].value("prepare_seconds", 0.0);
  }
  return cost;
}

// Seconds and model units of the timed runs of one group, one method, or all.
struct Scale {
  double seconds = 0.0, units = 0.0;
  void add(double run_seconds, double run_units) {
    seconds += run_seconds;
    units += run_units;
  }
  bool known() const { return units > 0.0 && seconds > 0.0; }
  double per_unit() const { return seconds / units; }
};

std::string group_key(const RunSpec& run) {
  return std::to_string(run.variant) + "/" + run.method + run.build.to_json().dump();
}

}  // namespace

ShardPlan plan_shards(const Experiment& experiment, int shards, const ResultPaths* paths) {
  ShardPlan plan;
  plan.experiment = experiment.name;
  plan.shards = shards;
  std::map<std::string, size_t> group_of;
  std::vector<StoredCost> stored(experiment.runs.size());
  std::vector<Scale> group_scale;
  std::map<std::string, Scale> method_scale;
  Scale all_scale;
  std::vector<double> group_prepare;  // uncached prepare() seconds, where a stored run says
  for (size_t i = 0; i < experiment.runs.size(); ++i) {
    const RunSpec& run = experiment.runs[i];
    auto [it, inserted] = group_of.insert({group_key(run), group_scale.size()});
    if (inserted) {
      group_scale.emplace_back();
      group_prepare.push_back(0.0);
    }
    plan.runs.push_back({run.key, run.method, run.label, it->second, 0, 0.0, false});
    if (!paths) continue;
    stored[i] = stored_cost(*paths, experiment, run);
    plan.runs.back().stored = stored[i].stored;
    if (!stored[i].timed) continue;
    double units = model_units(experiment, run);
    group_scale[it->second].add(stored[i].run_seconds, units);
    method_scale[run.method].add(stored[i].run_seconds, units);
    all_scale.add(stored[i].run_seconds, units);
    group_prepare[it->second] = std::max(group_prepare[it->second], stored[i].uncached_prepare);
  }
  // Only what is still to do is dealt out: a stored run costs its shard nothing.
  std::vector<double> group_cost(group_scale.size(), 0.0);
  for (size_t i = 0; i < experiment.runs.size(); ++i) {
    PlannedRun& planned = plan.runs[i];
    if (planned.stored) continue;
    const Scale& group = group_scale[planned.group];
    auto method = method_scale.find(planned.method);
    double per_unit = group.known()                                                  ? group.per_unit()
                      : method != method_scale.end() && method->second.known() ? method->second.per_unit()
                      : all_scale.known()                                            ? all_scale.per_unit()
                                                                                     : 1.0;
    planned.estimated_seconds = per_unit * model_units(experiment, experiment.runs[i]);
    if (group_cost[planned.group] == 0.0) group_cost[planned.group] += group_prepare[planned.group];
    group_cost[planned.group] += planned.estimated_seconds;
  }
  plan.timed_runs = 0;
  for (const StoredCost& cost : stored) plan.timed_runs += cost.timed ? 1 : 0;
  // Largest group first, to the least loaded shard; ties by group index and shard index: deterministic.
  std::vector<size_t> order(group_cost.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return group_cost[a] > group_cost[b]; });
  plan.shard_seconds.assign(static_cast<size_t>(shards), 0.0);
  std::vector<int> shard_of_group(group_cost.size(), 0);
  for (size_t group : order) {
    size_t least = static_cast<size_t>(
        std::min_element(plan.shard_seconds.begin(), plan.shard_seconds.end()) - plan.shard_seconds.begin());
    shard_of_group[group] = static_cast<int>(least);
    plan.shard_seconds[least] += group_cost[group];
  }
  for (PlannedRun& planned : plan.runs) {
    planned.shard = shard_of_group[planned.group];
    plan.shard_of[planned.key] = planned.shard;
  }
  return plan;
}

ShardPlan read_shard_plan(const std::string& path, const Experiment& experiment) {
  ShardPlan plan = read_shard_plan_file(path);
  if (plan.experiment != experiment.name) {
    throw InputError(fmt::format("{}: key 'experiment': expected '{}', found '{}'", path, experiment.name, plan.experiment));
  }
  bool same = plan.shard_of.size() == experiment.runs.size() && plan.runs.size() == experiment.runs.size();
  for (const RunSpec& run : experiment.runs) same = same && plan.shard_of.count(run.key) > 0;
  if (!same) {
    throw InputError(fmt::format("{}: key 'runs': expected the {} runs of {}, found {} other runs; the experiment "
                                 "changed since it was planned: plan it again with `causticbench slurm`",
                                 path, experiment.runs.size(), experiment.source, plan.runs.size()));
  }
  return plan;
}

}  // namespace causticbench
