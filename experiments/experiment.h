// Experiment files: a scene (with overrides), the reference settings, the methods with fixed knobs and
// sweeps, the frames, the repetitions and the paper's published values. See docs/experiment-format.md.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/hash.h"
#include "core/scene.h"
#include "experiments/report_settings.h"
#include "methods/param_dict.h"
#include "methods/registry.h"

namespace causticbench {

// One run: a method with every knob resolved. Its key is a hash of everything that determines its
// output (scene content, overrides, frames, method, knobs, repetitions), so results paths derive from
// the configuration and a sweep resumes where it stopped.
struct RunSpec {
  std::string key;
  size_t variant = 0;                       // index into Experiment::variants
  std::string method;
  std::string label;                        // entry + its swept values (+ " @variant"): one run
  std::string entry;                        // the experiment entry's label (default: the method's name)
  ParamSet params;                          // every knob, defaults filled in
  ParamSet build;                           // the build-phase subset
  ParamSet frame;                           // the frame-phase subset
  ParamSet render;                          // the render-phase subset
  std::map<std::string, std::string> swept;  // knob -> value text, for the knobs the sweep set
  nlohmann::json spec;                      // the canonical spec that was hashed
};

// One version of the experiment's scene: the base overrides with a variant's on top (a resolution, a
// camera, a light), and the reference that goes with it. Every method entry runs on every variant (or on
// those its `variants` list names). A
// variant may name a scene file of its own (an extremes or capability case: another object, another
// material); the base overrides then apply to that scene.
struct SceneVariant {
  std::string name;          // "default" for an experiment without `variants`
  nlohmann::json overrides;  // as applied (canonical): the base overrides merged with the variant's
  Scene scene;               // loaded, overrides applied
  std::string reference_key;
  std::string scene_path;    // the experiment's scene, or the variant's own `scene`
  std::string scene_hash;    // of that file's text: it enters the reference's and the runs' keys
  // Of what the loaded scene holds (scene_content_json: every object and light, with the content of its
  // mesh and environment map). Not in any key (shipped keys stay), but stored with each reference frame:
  // a frame whose assets changed since (a mesh or map edited in place) is computed again, and the runs
  // measured against the old copy are measured again (reference_cache.cpp).
  std::string content_hash;
};

struct Experiment {
  std::string name;
  std::string source;        // the experiment file
  std::string description;
  std::string scene_path;
  std::string scene_hash;    // of the scene file's text
  std::vector<SceneVariant> variants;  // at least one
  std::vector<int> frames;
  int repetitions = 3;
  // `seeds: N`: every stochastic run (one whose knobs have a seed) is measured with N seeds, its own and
  // the next N - 1 (experiments/seed_replicas.h); its metrics are their means with 95 % intervals. Not in
  // any run key: a run measured with fewer seeds than asked is measured again under the same key.
  int seeds = 1;
  // Stratified points per pixel at which every method is rendered and averaged (docs/metrics.md,
  // "pixel_samples"); 1: the pixel centre alone. In a run's key only when it is not 1.
  int pixel_samples = 1;
  std::vector<std::string> metrics;
  std::string primary_metric = "relmse";
  ParamSet reference_params;
  std::vector<RunSpec> runs;
  ReportSettings report;     // paper, claims, trade-offs, budgets: what the report compares (report_settings.h)
  // `empty_reference_expected: true`: an extremes experiment that means to run against a reference with no
  // caustic in view. Without it such a reference stops the run before any method runs; with it the runs
  // are stored and reported as "empty reference", not scored. It changes how runs are judged, not what
  // they compute, so it is no part of any run key.
  bool empty_reference_expected = false;
  // `plugins:` (paths relative to the file): loaded before the methods are read (methods/plugins.h); each
  // as PluginIdentity::to_json, in experiment.json only when there are any.
  std::vector<nlohmann::json> plugins;

  nlohmann::json to_json() const;
  std::vector<std::string> variant_names() const;
};

// An experiment expands to at most `max_runs` runs (default kDefaultMaximumRuns, at most
// kLargestMaximumRuns): the count is taken before expanding, and a larger sweep is refused with it.
// Validation costs about 5 KB and 70 us per run: 20,000 runs validate in 1.6 s at a peak resident
// size of 230 MB (140 MB of it the process itself), where 10^6 took 47 s and 5.3 GB.
constexpr int64_t kDefaultMaximumRuns = 20000;
constexpr int64_t kLargestMaximumRuns = 2000000;

// Reads, validates and expands an experiment file. Every defect is an InputError with file, line and
// column, raised before any work starts.
Experiment load_experiment(const std::string& path);
// The runs (key, method) the experiment file at `path` expands to, in order; empty when it cannot be read.
// What `causticbench status` names pending runs by (store/sweep_status.h).
std::vector<std::pair<std::string, std::string>> experiment_file_runs(const std::string& path);

// The expansion of one method entry: fixed knobs, cartesian `sweep` lists and paired `zip` lists.
// Exposed for tests. Each element maps knob name -> (value text, where it came from).
using KnobAssignment = std::map<std::string, ParamDict::Entry>;
std::vector<KnobAssignment> expand_sweep(const KnobAssignment& fixed,
                                         const std::vector<std::pair<std::string, std::vector<ParamDict::Entry>>>& sweep,
                                         const std::vector<std::pair<std::string, std::vector<ParamDict::Entry>>>& zip);


// --filter (and the claims' run selections): comma-separated terms, each `knob=value` (numbers compare
// numerically; also `method=NAME`) or a word that must appear in the run's label; a run matches when
// every term does. `knobs` is a JSON object of knob values.
bool matches_filter(const std::string& method, const std::string& label, const nlohmann::json& knobs,
                    const std::string& filter);
// A run also matches `variant=NAME` (the name of its scene variant).
bool run_matches_filter(const Experiment& experiment, const RunSpec& run, const std::string& filter);
// A --filter term that can match no run of the experiment is a typo that would select nothing and
// still succeed: a `knob=value` whose knob no method of the experiment has, a `method=` or `variant=`
// naming none of its methods or variants. InputError with "did you mean"; words without '=' (label
// words) are not checked.
void check_filter_terms(const Experiment& experiment, const std::string& filter);
// A stored record.json's knobs as filters and claims see them: build, frame then render knobs, and its
// variant and receiver_pixels when it has them.
nlohmann::json record_knobs(const nlohmann::json& record);
// --filter on a stored record.json (its method, label and record_knobs).
bool record_matches_filter(const nlohmann::json& record, const std::string& filter);
struct RunRecord;  // store/run_record.h
bool record_matches_filter(const RunRecord& record, const std::string& filter);

}  // namespace causticbench
