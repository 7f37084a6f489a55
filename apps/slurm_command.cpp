// `causticbench slurm`: turns experiments into Slurm jobs that share one results folder (docs/cluster.md).
// Per experiment, under RESULTS/<experiment>/slurm/: the shard plan (experiments/shard_plan.h), three job
// scripts and submit.sh, which submits them in order with their dependencies; `--submit` runs it. Every
// file is plain text to read and edit before submitting.
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "apps/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "core/shell.h"
#include "core/assets.h"
#include "experiments/experiment.h"
#include "store/result_paths.h"
#include "experiments/shard_plan.h"

namespace causticbench {

namespace fs = std::filesystem;

namespace {

// An #SBATCH argument: sbatch reads a directive's arguments as the shell would split words, with double
// quotes around a word that holds spaces and a backslash before a quote or a backslash. A '%' starts one
// of Slurm's file-name patterns (%j, %a, ...): a literal one in a path is written %%.
// `literal_percent`: the text is a path, not a pattern. Returns the text to put between double quotes.
std::string sbatch_escaped(const std::string& text, bool literal_percent) {
  std::string result;
  for (char c : text) {
    if (c == '"' || c == '\\') result += '\\';
    if (c == '%' && literal_percent) result += '%';
    result += c;
  }
  return result;
}

// A path or name that a job script will hold: a control character (a newline above all, which would end
// an #SBATCH line or a comment and run the rest as a command) can be neither quoted for sbatch nor kept
// out of a comment, so it is refused, before anything is written.
void check_job_text(const std::string& what, const std::string& text) {
  for (unsigned char c : text) {
    if (c < 0x20 || c == 0x7f) {
      std::string shown;
      for (unsigned char d : text) shown += d < 0x20 || d == 0x7f ? fmt::format("\\x{:02x}", d) : std::string(1, static_cast<char>(d));
      throw InputError(fmt::format("{}: expected a path or name without control characters (a job script cannot hold "
                                   "them: a newline would end its #SBATCH line and run the rest as a command), found "
                                   "'{}'",
                                   what, shown));
    }
  }
}

std::string this_program() {
  const std::string path = executable_path();
  return path.empty() ? "causticbench" : path;
}

// The #SBATCH lines every job gets: the resource options, then the user's extra lines as given.
std::string resource_lines(const SlurmOptions& options) {
  std::string lines;
  if (!options.partition.empty()) lines += "#SBATCH --partition=" + options.partition + "\n";
  if (!options.account.empty()) lines += "#SBATCH --account=" + options.account + "\n";
  if (!options.time.empty()) lines += "#SBATCH --time=" + options.time + "\n";
  if (options.cpus_per_task > 0) lines += fmt::format("#SBATCH --cpus-per-task={}\n", options.cpus_per_task);
  if (!options.memory.empty()) lines += "#SBATCH --mem=" + options.memory + "\n";
  for (const std::string& line : options.sbatch_lines) {
    lines += (line.rfind("#SBATCH", 0) == 0 ? line : "#SBATCH " + line) + "\n";
  }
  return lines;
}

void check_options(const SlurmOptions& options) {
  for (const std::string& line : options.sbatch_lines) {
    if (line.empty()) throw InputError("--sbatch: expected one option per line such as --qos=high, found ''");
    check_job_text("--sbatch", line);
  }
  check_job_text("--results", fs::absolute(options.results).lexically_normal().string());
  for (const std::string& file : options.experiments)
    check_job_text("experiment file " + file, fs::absolute(file).lexically_normal().string());
  check_job_text("this program's path", this_program());
  for (const auto& [name, value] : {std::pair{"--partition", options.partition}, {"--time", options.time},
                                    {"--mem", options.memory}, {"--account", options.account}}) {
    if (value.find_first_of(" \t\n\r'\"\\") != std::string::npos) {
      throw InputError(fmt::format("{}: expected a value without spaces or quotes, found '{}'", name, value));
    }
  }
}

struct JobFiles {
  std::string folder, submit;
};

JobFiles write_jobs(const SlurmOptions& options, const Experiment& experiment, const std::string& experiment_file,
                    const ShardPlan& plan) {
  ResultPaths paths{fs::absolute(options.results).lexically_normal().string()};
  const std::string folder = (fs::path(paths.experiment(experiment.name)) / "slurm").string();
  const std::string logs = folder + "/logs";
  make_folders(logs);  // Slurm does not create the folder of --output
  write_shard_plan(shard_plan_path(paths, experiment.name), plan);
  const std::string program = shell_quoted(this_program()), file = shell_quoted(experiment_file), results = shell_quoted(paths.results);
  const std::string common = resource_lines(options);
  // The runner's threads follow the job's CPUs, so editing --cpus-per-task here is enough.
  const std::string threads = "--threads \"${SLURM_CPUS_PER_TASK:-1}\"";
  // sbatch reads #SBATCH lines only up to the first command: every one of them comes first.
  auto header = [&](const std::string& what, const std::string& job, const std::string& log, const std::string& more = "") {
    return fmt::format("#!/bin/bash\n# {} of experiment {} ({}), written by `causticbench slurm`; edit freely.\n"
                       "#SBATCH {}\n#SBATCH {}\n{}{}set -euo pipefail\n",
                       what, experiment.name, experiment_file,
                       "\"--job-name=" + sbatch_escaped(fmt::format("cb-{}-{}", experiment.name, job), false) + "\"",
                       // The job's own patterns (%j, %a, %A) stay patterns; the folder's '%' are literal.
                       "\"--output=" + sbatch_escaped(logs, true) + "/" + log + "\"", more, common);
  };
  write_text_atomically(folder + "/prepare.sbatch",
                        header("Every missing reference and build", "prepare", "prepare-%j.out") +
                            fmt::format("exec {} run {} --results {} --prepare-only {}\n", program, file, results, threads));
  write_text_atomically(
      folder + "/shards.sbatch",
      header(fmt::format("The {} shards (one array task each; resubmit one with sbatch --array=I)", plan.shards),
             "shards", "shard-%a-%A.out",
             // A failed prepare job cancels the array (rather than leaving it pending for ever); the
             // report job then runs and shows what is stored.
             fmt::format("#SBATCH --array=0-{}\n#SBATCH --kill-on-invalid-dep=yes\n", plan.shards - 1)) +
          fmt::format("exec {} run {} --results {} --shard \"${{SLURM_ARRAY_TASK_ID}}/{}\" "
                      "--shard-plan {} --no-report {}\n",
                      program, file, results, plan.shards,
                      shell_quoted(shard_plan_path(paths, experiment.name)), threads));
  write_text_atomically(folder + "/report.sbatch",
                        header("The report", "report", "report-%j.out") +
                            fmt::format("{} status {} || true\nexec {} report {}\n", program,
                                        shell_quoted(paths.experiment(experiment.name)), program,
                                        shell_quoted(paths.experiment(experiment.name))));
  // afterok: shards start only on a complete reference; afterany: the report is written even when a shard
  // was killed (it shows what is stored; `causticbench status` names the shards to resubmit).
  const std::string submit = folder + "/submit.sh";
  write_text_atomically(
      submit,
      fmt::format("#!/bin/bash\n# Submits the jobs of experiment {} in order; written by `causticbench slurm`.\n"
                  "set -euo pipefail\ncd \"$(dirname \"$0\")\"\n"
                  "prepare=$(sbatch --parsable prepare.sbatch); prepare=${{prepare%%;*}}\n"
                  "shards=$(sbatch --parsable --dependency=afterok:$prepare shards.sbatch); shards=${{shards%%;*}}\n"
                  "report=$(sbatch --parsable --dependency=afterany:$shards report.sbatch); report=${{report%%;*}}\n"
                  "echo \"{}: prepare job $prepare, shard array $shards ({} shards), report job $report\"\n"
                  "echo \"$prepare $shards $report\" > jobs\n",
                  experiment.name, experiment.name, plan.shards));
  fs::permissions(submit, fs::perms::owner_exec | fs::perms::group_exec, fs::perm_options::add);
  return {folder, submit};
}

}  // namespace

int run_slurm(const SlurmOptions& options) {
  check_options(options);
  check_results_folder(options.results);
  // Every experiment is loaded and checked before anything is written.
  std::vector<Experiment> experiments;
  for (const std::string& file : options.experiments) {
    experiments.push_back(load_experiment(file));
    check_job_text("experiment name", experiments.back().name);
  }
  ResultPaths paths{options.results};
  for (size_t i = 0; i < experiments.size(); ++i) {
    const Experiment& experiment = experiments[i];
    ShardPlan plan = plan_shards(experiment, options.shards, &paths);
    size_t stored = 0;
    for (const PlannedRun& run : plan.runs) stored += run.stored ? 1 : 0;
    JobFiles jobs = write_jobs(options, experiment, fs::absolute(options.experiments[i]).lexically_normal().string(), plan);
    std::vector<std::string> loads;
    for (double seconds : plan.shard_seconds) loads.push_back(fmt::format("{:.3g}", seconds));
    fmt::print("{}: {} runs, {} to do, in {} shards; estimated cost per shard: {} ({})\n", experiment.name,
               plan.runs.size(), plan.runs.size() - stored, plan.shards, join(loads, ", "),
               plan.timed_runs > 0 ? fmt::format("seconds, scaled by the timings of {} stored runs", plan.timed_runs)
                                   : std::string("model units: nothing stored to scale them by"));
    fmt::print("  jobs: {}/prepare.sbatch, shards.sbatch, report.sbatch; submit with {}\n", jobs.folder, jobs.submit);
    if (options.submit) {
      std::string command = "bash " + shell_quoted(jobs.submit) + " 2>&1";
      FILE* pipe = ::popen(command.c_str(), "r");
      if (!pipe) throw WriteError("cannot run " + command);
      std::string output;
      char buffer[512];
      while (size_t read = std::fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, read);
      int status = ::pclose(pipe);
      fmt::print("{}", output);
      if (status != 0) {
        throw InputError(fmt::format("--submit: {} failed (is sbatch on PATH and the cluster reachable?): {}", jobs.submit,
                                     output));
      }
    }
  }
  return 0;
}

}  // namespace causticbench
