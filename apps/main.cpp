// causticbench: real-time caustics methods behind one interface, measured against a converged reference.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "apps/commands.h"
#include "core/errors.h"
#include "core/files.h"
#include "core/progress.h"
#include "methods/plugins.h"
#include "methods/registry.h"

namespace {

// A bound for --threads only so that CLI11's message stays readable ("not in range 0 to 65536"); what
// matters is that a negative count is refused.
constexpr int kMaximumThreads = 65536;

// A path option must name something: an empty one would resolve to the current folder's parent's root
// ("wrote /caustic.exr") or stop with an internal error.
const CLI::Validator kNonEmptyPath(
    [](std::string& value) { return value.empty() ? std::string("expected a path, found an empty one") : std::string(); },
    "PATH");

// A number option must be finite: CLI::Range lets NaN through (every comparison with it is false).
const CLI::Validator kFiniteNumber(
    [](std::string& value) {
      try {
        size_t used = 0;
        const double number = std::stod(value, &used);
        if (used == value.size() && std::isfinite(number)) return std::string();
      } catch (const std::exception&) {
      }
      return "expected a finite number, found '" + value + "'";
    },
    "NUMBER");

}  // namespace

int main(int argc, char** argv) {
  using namespace causticbench;
  CLI::App app{
      "causticbench: caustics rendering methods from the literature behind one interface, each measured against a\n"
      "converged reference. Every method writes caustic irradiance E_c (W/m^2, RGB) at the same G-buffer points.\n"
      "Exit codes: 0 success, 1 internal failure, 2 bad input (scene, knob, command line), nothing written."};
  app.require_subcommand(1);
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "no progress lines");
  std::vector<std::string> plugin_paths;
  app.add_option("--plugin", plugin_paths,
                 "load the methods of a plugin, a shared library built against the causticbench SDK (docs/sdk.md);\n"
                 "repeatable, before or after the subcommand; also CAUSTICBENCH_PLUGINS=PATH:PATH and an experiment's\n"
                 "plugins: list")
      ->allow_extra_args(false)
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);  // one path per --plugin: never the arguments after it
  // Options of the main command (--plugin, --quiet) may follow the subcommand's.
  app.fallthrough();

  RenderOptions render;
  CLI::App* render_command = app.add_subcommand(
      "render", "Render one frame of a scene with one method; writes caustic.exr (E_c), direct.exr, gbuffer.exr,\n"
                "composite.png, caustic.png and record.json (settings, timings, counters) into --out.");
  render_command->add_option("scene", render.scene, "scene file (YAML, see docs/scene-format.md)")->required();
  render_command->add_option("-m,--method", render.method, "method name (see `causticbench list`)")->capture_default_str();
  render_command->add_option("-s,--set", render.assignments, "knob=value, repeatable (see `causticbench describe METHOD`)");
  render_command->add_option("-o,--out", render.out, "output folder")->required()->check(kNonEmptyPath);
  render_command->add_option("-f,--frame", render.frame, "frame index of an animated scene")->capture_default_str();
  render_command->add_option("-t,--threads", render.threads, "worker threads (0: all cores)")
      ->capture_default_str()->check(CLI::Range(0, kMaximumThreads));
  render_command->add_option("-r,--resolution", render.resolution, "override the camera resolution, WIDTHxHEIGHT");
  render_command->add_option("--direct-samples", render.direct_samples, "light samples per pixel for direct.exr")
      ->capture_default_str()->check(CLI::Range(1, 4096));
  render_command->add_option("--pixel-samples", render.pixel_samples,
                             "render the method at N stratified points per pixel (a square: 1, 4, 9, ...) and\n"
                             "average them, as an experiment's pixel_samples does (docs/metrics.md)")
      ->capture_default_str()->check(CLI::Range(1, 256));
  render_command->add_option("--build-cache", render.build_cache,
                             "folder of stored builds (e.g. results/builds): a method that precomputes loads its build\n"
                             "from there when stored and stores it otherwise (see docs/results-format.md)");
  const std::vector<std::string> dumpable = methods_with_gpu_backend();
  render_command->add_option("--dump-frame", render.dump_frame,
                             "also write the frame's GPU inputs and this backend's output into DIR, for\n"
                             "causticbench-gpubench DIR and causticbench gpu-compare DIR (methods: " +
                                 join(dumpable, ", ") + ")");

  ExportOptions exported;
  CLI::App* export_command = app.add_subcommand(
      "export", "Write one frame of a scene as the `external` method hands it to a program: scene.json (a\n"
                "causticbench scene of that frame alone), world.json (the frame in world space), its meshes and\n"
                "environment maps, and gbuffer.exr, into --out (methods/external/README.md).");
  export_command->add_option("scene", exported.scene, "scene file (YAML, see docs/scene-format.md)")->required();
  export_command->add_option("-o,--out", exported.out, "output folder")->required()->check(kNonEmptyPath);
  export_command->add_option("-f,--frame", exported.frame, "frame index of an animated scene")->capture_default_str();
  export_command->add_option("-r,--resolution", exported.resolution, "override the camera resolution, WIDTHxHEIGHT");

  ExperimentOptions experiment;
  CLI::App* run_command = app.add_subcommand(
      "run", "Run an experiment (docs/experiment-format.md): expand its sweeps into runs, compute or reuse the\n"
             "cached reference, time and measure every run not yet stored under RESULTS/<experiment>/runs/<key>/,\n"
             "then write the report. A killed run resumes where it stopped.");
  run_command->add_option("experiment", experiment.experiment, "experiment file (YAML)")->required();
  run_command->add_option("--results", experiment.results, "results folder")->capture_default_str()->check(kNonEmptyPath);
  run_command->add_flag("--dry-run", experiment.dry_run, "list the runs (stored or pending) and exit");
  run_command->add_flag("--force", experiment.force, "rerun runs that are already stored");
  run_command->add_option("--filter", experiment.filter,
                          "only runs matching every comma-separated term: knob=value, method=NAME, or a word of the label");
  run_command->add_option("--shard", experiment.shard,
                          "run only slice i of n (i/n, 0-based): the unit a scheduler hands out. Runs sharing one\n"
                          "prepare() stay together and groups are dealt out by estimated cost (docs/cluster.md)");
  run_command->add_option("--shard-plan", experiment.shard_plan,
                          "with --shard: take the partition from this plan (RESULTS/<experiment>/slurm/shard-plan.json,\n"
                          "written once by `causticbench slurm`), so that shards started at different times agree");
  run_command->add_flag("--prepare-only", experiment.prepare_only,
                        "only compute the missing references and builds of the selected runs, then exit (the job\n"
                        "the shards of a cluster sweep wait for)");
  run_command->add_option("-t,--threads", experiment.threads, "worker threads (0: all cores)")
      ->capture_default_str()->check(CLI::Range(0, kMaximumThreads));
  run_command->add_flag("!--no-report", experiment.report, "do not write the report after the runs");

  std::string report_folder;
  CLI::App* report_command = app.add_subcommand(
      "report", "Write report.html, viewer.html, report.md, results.csv and results.json for RESULTS/<experiment>/ from the stored runs.");
  report_command->add_option("folder", report_folder, "an experiment's results folder")->required();
  bool recompute_metrics = false;
  double viewer_megabytes = kDefaultViewerMegabytes;
  report_command
      ->add_option("--viewer-mb", viewer_megabytes,
                   "what the viewer's pixel files of frames beyond each run's first may take, in MB (every k-th frame "
                   "of every run, the least k that fits; 0: first frames only)")
      ->capture_default_str()
      ->check(kFiniteNumber)
      ->check(CLI::Range(0.0, 1e6));
  report_command->add_flag("--recompute-metrics", recompute_metrics,
                           "first compute every metric of experiment.json again from the stored images (after a metric\n"
                           "was added or fixed), rewriting each run's record atomically; no method is run");

  std::vector<std::string> summarize_folders;
  std::string summarize_out;
  CLI::App* summarize_command = app.add_subcommand(
      "summarize", "Write one page across several experiments (a study, e.g. RESULTS/study_*): summary.html, summary.md\n"
                   "and summary.json with, per scene, the best method and knobs per frame budget; per method, where it\n"
                   "wins and where it fails; the cost model (prepare s, memory, frame ms) with break-even frame counts;\n"
                   "and every claim with its verdict (docs/reports.md, \"The study's summary\").");
  summarize_command->add_option("folders", summarize_folders, "experiments' results folders, RESULTS/<experiment>")
      ->required();
  summarize_command->add_option("-o,--out", summarize_out,
                                "folder for the three files (default: the folder holding the first experiment's, RESULTS)");

  SlurmOptions slurm;
  CLI::App* slurm_command = app.add_subcommand(
      "slurm", "Write Slurm jobs for sweeps on a cluster sharing RESULTS (docs/cluster.md): per experiment, under\n"
               "RESULTS/<experiment>/slurm/, a shard plan, a job computing every missing reference and build, an array\n"
               "of --shards jobs depending on it (afterok), a report job depending on the array, and submit.sh,\n"
               "which submits them in that order. Plain files: read and edit them, then run submit.sh or use --submit.");
  slurm_command->add_option("experiments", slurm.experiments, "experiment files (YAML)")->required();
  slurm_command->add_option("--shards", slurm.shards, "array jobs per experiment")->required()->check(CLI::Range(1, 10000));
  slurm_command->add_option("--results", slurm.results, "results folder, on a filesystem every node mounts")
      ->capture_default_str()
      ->check(kNonEmptyPath);
  slurm_command->add_flag("--submit", slurm.submit, "also submit the jobs with sbatch (runs submit.sh)");
  slurm_command->add_option("--partition", slurm.partition, "#SBATCH --partition of every job");
  slurm_command->add_option("--time", slurm.time, "#SBATCH --time of every job (e.g. 4:00:00)");
  slurm_command->add_option("--cpus-per-task", slurm.cpus_per_task,
                            "#SBATCH --cpus-per-task of every job; also the runner's --threads")
      ->check(CLI::Range(1, kMaximumThreads));
  slurm_command->add_option("--mem", slurm.memory, "#SBATCH --mem of every job (e.g. 16G)");
  slurm_command->add_option("--account", slurm.account, "#SBATCH --account of every job");
  slurm_command->add_option("--sbatch", slurm.sbatch_lines,
                            "an extra #SBATCH line for every job, e.g. --sbatch=--qos=long (repeatable)")
      ->allow_extra_args(false)
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);  // one line per --sbatch: never the experiments after it

  std::string status_folder;
  CLI::App* status_command = app.add_subcommand(
      "status", "How far a sweep is: runs stored ok, failed and pending, per method, and the shards of its plan\n"
                "that still have runs to do. Exit code 0 when no run is pending, 3 otherwise.");
  status_command->add_option("folder", status_folder, "an experiment's results folder, RESULTS/<experiment>")->required();

  std::string compare_folder;
  CLI::App* compare_command = app.add_subcommand(
      "gpu-compare", "Compare causticbench-gpubench's output (vulkan_irradiance.bin) with the CPU backend's\n"
                     "(cpu_irradiance.bin) in a --dump-frame folder; exit 1 when they disagree beyond the tolerance.");
  compare_command->add_option("folder", compare_folder, "a --dump-frame folder")->required();

  CLI::App* list_command = app.add_subcommand("list", "List the methods and their capability matrix.");
  std::string describe_name;
  bool markdown = false;
  CLI::App* describe_command = app.add_subcommand("describe", "Print a method's knobs (name, phase, type, default, range, meaning).");
  describe_command->add_option("method", describe_name, "method name")->required();
  describe_command->add_flag("--markdown", markdown, "print the table as Markdown (the method's README table)");
  bool quick_knobs = false;
  describe_command->add_flag("--quick-knobs", quick_knobs,
                             "print only the method's quick knobs, one `knob=value` a line: a cheap setting for smoke runs "
                             "(scripts/render_every_method.sh, the conformance tests)");
  std::string conform_method;
  CLI::App* conform_command = app.add_subcommand(
      "conform", "Run the conformance and capability checks every built-in method passes on a plugin's methods\n"
                 "(--plugin PATH; all of its methods, or METHOD): the same suites, by causticbench-conformance.\n"
                 "Prints each check and what failed; exit code 0 when all pass, 1 when one fails (docs/sdk.md).");
  conform_command->add_option("method", conform_method, "one method (default: every method of the loaded plugins)");
  std::string validate_file;
  CLI::App* validate_command = app.add_subcommand("validate", "Check a scene or experiment file; the first defect is reported with file, line, column, key, expected\nand found.");
  validate_command->add_option("file", validate_file, "scene or experiment file")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    int code = app.exit(error);
    return code == 0 ? 0 : 2;
  }
  Progress::set_quiet(quiet);
  try {
    // Every refusal (another SDK version, a name clash, a registration that throws) exits 2 before any work.
    load_plugins_from_environment();
    for (const std::string& path : plugin_paths) load_plugin(path);
    if (*render_command) return run_render(render);
    if (*export_command) return run_export(exported);
    if (*run_command) return run_experiment_command(experiment);
    if (*report_command) return run_report(report_folder, recompute_metrics, viewer_megabytes);
    if (*summarize_command) return run_summarize(summarize_folders, summarize_out);
    if (*slurm_command) return run_slurm(slurm);
    if (*status_command) return run_status(status_folder);
    if (*compare_command) return run_gpu_compare(compare_folder);
    if (*list_command) return run_list();
    if (*describe_command) return run_describe(describe_name, markdown, quick_knobs);
    if (*validate_command) return run_validate(validate_file);
    if (*conform_command) return run_conform(conform_method);
  } catch (const InputError& error) {
    fmt::print(stderr, "error: {}\n", error.what());
    return 2;
  } catch (const ProgramError& error) {
    fmt::print(stderr, "error: {}\n", error.what());
    return 1;
  } catch (const MethodError& error) {
    fmt::print(stderr, "error: {}\n", error.what());
    return 1;
  } catch (const WriteError& error) {
    // The environment's fault (a full disk, a folder made read-only), not the input's nor a bug.
    fmt::print(stderr, "error: {}\n", error.what());
    return 1;
  } catch (...) {
    fmt::print(stderr, "internal error: {}\n", current_exception_text());
    return 1;
  }
  return 0;
}
