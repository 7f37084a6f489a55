// The record of one run, runs/<run_key>/record.json (docs/results-format.md): the one definition that
// the runner writes (run_measurement.h), the store checks (record_check.h), `report --recompute-metrics`
// rewrites and the report, results.csv and results.json read. Versioned: a record carries
// "record_version"; an older one is read through upgrade_run_record(), the one upgrade step, and a newer
// one is refused with a message that says so.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "methods/method.h"
#include "metrics/confidence.h"

namespace causticbench {

// Version 1: records before "record_version" (no git revision, no reference settings).
// Version 2: "record_version", "git_revision", "reference_settings".
inline constexpr int kRunRecordVersion = 2;

// A record that cannot be read: what is wrong, as "field 'frames' is missing".
class RecordError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One rendered frame of a run. A metric stored as JSON null (psnr of an exact image is +inf, which JSON
// cannot hold) reads as NaN and is written back as null.
struct FrameRecord {
  int frame = 0;
  std::string image;  // "frame_NNNN.exr" in the run's folder
  std::vector<double> update_ms, render_ms, gpu_render_ms;  // one value per timed pass
  std::map<std::string, double> metrics;
  std::map<std::string, std::string> metrics_undefined;  // metric -> why it has no value
  std::map<std::string, std::map<std::string, double>> metric_parameters;  // flip -> its exposure range, ...
};

// Minimum and median over every timed pass of every frame.
struct RunTimings {
  double update_ms_min = 0, update_ms_median = 0, render_ms_min = 0, render_ms_median = 0;
  double frame_ms_min = 0, frame_ms_median = 0;
  std::optional<double> gpu_render_ms_min, gpu_render_ms_median;  // Vulkan backends only
  std::optional<double> field(const std::string& name) const;     // "frame_ms_median", ...
};

// How the method's prepare() result was obtained (methods/lifecycle.h, PrepareOutcome).
struct PrepareRecord {
  std::string source = "computed";  // computed, loaded, recomputed
  std::string build_key;            // empty: not cached
  double prepare_seconds = 0, load_seconds = 0, save_seconds = 0;
  std::string warning;              // recomputed: why the stored build was not used
};

// What the run's configuration could not represent (methods/method.h, LostFlux): the worst frame's (its
// fraction the largest over the frames) and each frame's fraction (NaN where a frame reported none).
struct LostFluxRecord {
  LostFlux worst;
  std::vector<double> frames;
  std::vector<double> moved_frames;  // each frame's LostFlux::moved (empty: none moved any, or an older record)
};

// The record of the lost flux of a run's frames (CausticMethod::lost_flux per frame); none when no frame
// reported one.
std::optional<LostFluxRecord> lost_flux_record(const std::vector<std::optional<LostFlux>>& frames);

// One seed's measurement of a run measured with several seeds (an experiment's `seeds`): its frames
// (images, timings, metrics) and its metrics over them, as a run measured once holds them.
struct SeedRun {
  int64_t seed = 0;
  std::vector<FrameRecord> frames;
  std::map<std::string, double> metrics;
  std::map<std::string, std::string> metrics_undefined;
};

// Record "seeds" (docs/results-format.md): the seeds a stochastic run was measured with, the first its
// own (its knobs' seed; its images are the run's frames), and what they give together. The run's
// metrics and its frames' metrics are the means over the seeds (experiments/seed_replicas.h).
struct SeedsRecord {
  std::vector<SeedRun> runs;
  std::map<std::string, MetricInterval> intervals;  // every run metric defined on every seed
  std::vector<std::string> stddev_images;           // per frame (the record's order): per-pixel standard deviation
};

struct RunRecord {
  int record_version = kRunRecordVersion;
  std::string key, status = "ok", error, method, label;
  // The experiment entry the run came from (its `label`, the method's name by default): what the report's
  // columns, legends and summary name. A record written before the field: entry_of_label below.
  std::string entry;
  std::string variant, reference_key;  // empty in a version-1 record written before scene variants
  std::string git_revision;            // of the causticbench that measured it; empty when unknown (version 1)
  // The resolved reference knobs the run's reference was computed with (experiment.json "reference" at
  // the time); null when unknown (version 1).
  nlohmann::json reference_settings;
  // The run's resolved knobs per phase, the knobs its sweep set, and the spec its key hashes.
  nlohmann::json build = nlohmann::json::object(), frame = nlohmann::json::object(),
                 render = nlohmann::json::object(), swept = nlohmann::json::object(), spec;
  std::optional<int64_t> receiver_pixels;  // of the first frame's G-buffer (ok runs)

  // Ok runs only:
  std::vector<FrameRecord> frames;
  PrepareRecord prepare;
  RunTimings timings;
  std::map<std::string, double> metrics;                 // mean over frames; + temporal_flicker
  std::map<std::string, std::string> metrics_undefined;  // metric -> why (the first undefined frame's reason)
  std::optional<std::vector<int>> empty_reference_frames;  // empty_reference_expected: frames with no caustic
  std::string empty_reference_reason;
  int64_t memory_bytes = 0, peak_rss_bytes = 0;
  std::map<std::string, double> counters;
  nlohmann::json method_record = nlohmann::json::object();
  std::optional<LostFluxRecord> lost_flux;  // methods that report it (not the reference)
  nlohmann::json images;            // {"frame_0000.exr": {"bytes", "xxhash"}}: set by the store
  nlohmann::json reference_images;  // the reference images it was measured against
  std::optional<bool> reference_converged;  // empty: written before the flag (taken as converged)
  std::string reference_unconverged;        // why not, when false
  std::optional<SeedsRecord> seeds;         // measured with several seeds (an experiment's `seeds`)

  bool ok() const { return status == "ok"; }
  // A metric's value: none when absent, NaN (a null in the file) or undefined.
  std::optional<double> metric(const std::string& name) const;
  // Whether its output depends on a seed: its resolved knobs have one.
  bool stochastic() const { return knobs().contains("seed"); }
  // How many seeds it was measured with (1 without a "seeds" block).
  int seed_count() const { return seeds ? static_cast<int>(seeds->runs.size()) : 1; }
  // The 95 % interval of a metric: over its seeds when it has several; zero width (count 1) when the run
  // is deterministic; none for a stochastic run measured once, or a metric without a value.
  std::optional<MetricInterval> interval(const std::string& name) const;
  // Any quantity of the registry (methods/quantity_registry.h) by name: metric, timing, size or
  // counter; none when the record has no finite value of it.
  std::optional<double> quantity(const std::string& name) const;
  // The resolved knobs that --filter and claims match: build, frame and render merged, with variant
  // and receiver_pixels.
  nlohmann::json knobs() const;

  nlohmann::json to_json() const;
  // Reads a record of any version this build knows (upgrading it first); throws RecordError naming the
  // first field that is missing or of the wrong type, or saying the record is of a newer version.
  static RunRecord from_json(const nlohmann::json& stored);
};

// The one upgrade step: a record of an older version as the current version would hold it (version 1
// gets record_version 2, an empty git_revision and null reference_settings: "unknown"). The current
// version is returned as it is; a newer one throws RecordError.
nlohmann::json upgrade_run_record(nlohmann::json stored);

// The entry label of a run label ("lpi grid vector grid_resolution=64 @small" -> "lpi grid vector"): the
// label without its variant suffix and the " knob=value" words of the knobs the sweep set.
std::string entry_of_label(const std::string& label, const std::string& variant, const nlohmann::json& swept);

// How many seeds a stored ok record was measured with (its "seeds" runs, else 1), read without parsing the
// whole record; a failed record counts as measured with any number (it is not run again for its seeds).
// Whether `seeds` asked of a run is more than it holds: a stochastic run (its knobs have a seed) of fewer.
int stored_seed_count(const nlohmann::json& stored);
bool stored_with_fewer_seeds(const nlohmann::json& stored, int seeds);

// The record's version as stored (1 when it has no "record_version").
int stored_record_version(const nlohmann::json& stored);

}  // namespace causticbench
