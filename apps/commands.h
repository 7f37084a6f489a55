// The subcommands of the causticbench command line.
#pragma once

#include <string>
#include <vector>

#include "core/scene.h"
#include "reports/report.h"

namespace causticbench {

struct RenderOptions {
  std::string scene;
  std::string method = "reference";
  std::vector<std::string> assignments;  // key=value knobs
  std::string out;
  int frame = 0;
  int threads = 0;
  std::string resolution;  // "WxH" or empty
  int direct_samples = 16;
  int pixel_samples = 1;   // stratified points per pixel the method renders and averages (a square)
  std::string dump_frame;  // folder for causticbench-gpubench, or empty
  std::string build_cache;  // folder of stored builds (e.g. results/builds), or empty
};

int run_render(const RenderOptions& options);
// The scene file at `path`, at `resolution` ("WxH", as --resolution takes it) when that is not empty;
// InputError naming the file or --resolution.
Scene load_scene_at_resolution(const std::string& path, const std::string& resolution);

struct ExportOptions {
  std::string scene;
  std::string out;
  int frame = 0;
  std::string resolution;  // "WxH" or empty
};

int run_export(const ExportOptions& options);

struct ExperimentOptions {
  std::string experiment;
  std::string results = "results";
  bool dry_run = false;
  bool force = false;
  std::string filter;
  std::string shard;  // "i/n" or empty
  int threads = 0;
  bool report = true;  // write the report after the runs
  std::string shard_plan;     // a plan file of `causticbench slurm`, or empty
  bool prepare_only = false;  // only the missing references and builds
};

int run_experiment_command(const ExperimentOptions& options);
// `causticbench slurm`: job scripts (and with `submit`, their submission) for sweeps on a Slurm cluster.
struct SlurmOptions {
  std::vector<std::string> experiments;
  int shards = 1;
  std::string results = "results";
  std::string partition, time, memory, account;
  int cpus_per_task = 0;  // 0: not set (Slurm's default of 1)
  std::vector<std::string> sbatch_lines;
  bool submit = false;
};

int run_slurm(const SlurmOptions& options);
// Exit code 0 when every run is stored, 3 when runs are pending.
int run_status(const std::string& folder);
// `conform [METHOD]`: the conformance and capability suites on a plugin's methods (apps/conform_command.cpp).
int run_conform(const std::string& method);
int run_report(const std::string& folder, bool recompute_metrics = false, double viewer_megabytes = kDefaultViewerMegabytes);
// `causticbench summarize`: the study's summary across experiment folders, into `out` (empty: the first
// folder's parent).
int run_summarize(const std::vector<std::string>& folders, const std::string& out);
int run_gpu_compare(const std::string& folder);
int run_list();
int run_describe(const std::string& method, bool markdown, bool quick_knobs);
int run_validate(const std::string& file);

// "WxH" -> width, height; InputError otherwise.
void parse_resolution(const std::string& text, int& width, int& height);

}  // namespace causticbench
