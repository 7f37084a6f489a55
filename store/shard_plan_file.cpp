#include "store/shard_plan_file.h"

#include <filesystem>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "store/store_files.h"

namespace causticbench {

nlohmann::json ShardPlan::to_json() const {
  nlohmann::json runs_json = nlohmann::json::array();
  for (const PlannedRun& run : runs) {
    runs_json.push_back({{"key", run.key}, {"method", run.method}, {"label", run.label}, {"group", run.group},
                         {"shard", run.shard}, {"estimated_seconds", run.estimated_seconds}, {"stored", run.stored}});
  }
  return {{"experiment", experiment},
          {"shards", shards},
          {"timed_runs", timed_runs},
          {"shard_estimated_seconds", shard_seconds},
          {"runs", runs_json}};
}

std::string shard_plan_path(const ResultPaths& paths, const std::string& experiment_name) {
  return paths.experiment(experiment_name) + "/slurm/shard-plan.json";
}

void write_shard_plan(const std::string& path, const ShardPlan& plan) {
  make_folders(std::filesystem::path(path).parent_path().string());
  write_text_atomically(path, plan.to_json().dump(2) + "\n");
}

ShardPlan read_shard_plan_file(const std::string& path) {
  std::optional<std::string> text = read_file_bytes(path);
  if (!text) throw InputError(fmt::format("{}: shard plan missing or unreadable (written by `causticbench slurm`)", path));
  nlohmann::json json = nlohmann::json::parse(*text, nullptr, false);
  ShardPlan plan;
  try {
    if (json.is_discarded()) throw std::runtime_error("not valid JSON");
    plan.experiment = json.at("experiment").get<std::string>();
    plan.shards = json.at("shards").get<int>();
    plan.timed_runs = json.value("timed_runs", size_t{0});
    plan.shard_seconds = json.at("shard_estimated_seconds").get<std::vector<double>>();
    for (const nlohmann::json& run : json.at("runs")) {
      plan.runs.push_back({run.at("key").get<std::string>(), run.at("method").get<std::string>(),
                           run.at("label").get<std::string>(), run.at("group").get<size_t>(), run.at("shard").get<int>(),
                           run.at("estimated_seconds").get<double>(), run.value("stored", false)});
      if (plan.runs.back().shard < 0 || plan.runs.back().shard >= plan.shards) throw std::runtime_error("a shard out of range");
      plan.shard_of[plan.runs.back().key] = plan.runs.back().shard;
    }
    if (plan.shards < 1) throw std::runtime_error("shards below 1");
  } catch (const std::exception& error) {
    throw InputError(fmt::format("{}: not a shard plan ({})", path, error.what()));
  }
  return plan;
}

}  // namespace causticbench
