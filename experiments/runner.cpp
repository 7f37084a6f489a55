#include "experiments/runner.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/image_statistics.h"
#include "core/progress.h"
#include "experiments/reference_frames.h"
#include "experiments/result_store.h"
#include "methods/lifecycle.h"
#include "methods/method_runner.h"
#include "metrics/caustic_presence.h"
#include "metrics/metrics.h"

namespace causticbench {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

void parse_shard(const std::string& text, int& index, int& count) {
  size_t slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    size_t used_i = 0, used_n = 0;
    index = std::stoi(text.substr(0, slash), &used_i);
    count = std::stoi(text.substr(slash + 1), &used_n);
    if (used_i != slash || used_n != text.size() - slash - 1 || count < 1 || index < 0 || index >= count) {
      throw std::invalid_argument("range");
    }
  } catch (const std::exception&) {
    throw InputError(fmt::format("--shard: expected i/n with 0 <= i < n, found '{}'", text));
  }
}

namespace {


size_t peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<size_t>(usage.ru_maxrss) * 1024;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  size_t n = values.size();
  return n == 0 ? 0.0 : (n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]));
}

double minimum(const std::vector<double>& values) {
  return values.empty() ? 0.0 : *std::min_element(values.begin(), values.end());
}

// The fields that say which run a record is, for finished and failed runs alike.
nlohmann::json run_identity(const Experiment& experiment, const RunSpec& run) {
  const SceneVariant& variant = experiment.variants.at(run.variant);
  return {{"key", run.key},
          {"method", run.method},
          {"label", run.label},
          {"variant", variant.name},
          {"reference_key", variant.reference_key},
          {"build", run.build.to_json()},
          {"frame", run.frame.to_json()},
          {"render", run.render.to_json()},
          {"swept", run.swept},
          {"spec", run.spec}};
}

struct RunOutcome {
  nlohmann::json record;
  std::vector<std::pair<int, Image>> images;
};

nlohmann::json prepare_json(const PrepareOutcome& prepare) {
  nlohmann::json result = {{"source", prepare.source},
                           {"build_key", prepare.build_key},
                           {"prepare_seconds", prepare.prepare_seconds},
                           {"load_seconds", prepare.load_seconds},
                           {"save_seconds", prepare.save_seconds}};
  if (!prepare.warning.empty()) result["warning"] = prepare.warning;
  return result;
}

// A frame whose reference is empty is not scored: every metric of it is undefined, except the count of
// non-finite pixels, which judges the method alone.
void mark_empty_reference(MetricValues& values, const CausticPresence& presence) {
  std::string reason = "empty reference: " + presence.describe();
  for (auto it = values.values.begin(); it != values.values.end();) {
    if (it->first == "nonfinite_pixels") {
      ++it;
      continue;
    }
    values.undefined[it->first] = reason;
    it = values.values.erase(it);
  }
  for (auto& [name, why] : values.undefined) why = reason;
}

// The run's metrics over its frames: each the mean of its per-frame values (nonfinite_pixels: the sum),
// or undefined when it is undefined on any frame, with the first such frame's reason: a mean over some of
// the frames would not compare with other runs' means over all of them.
struct RunMetrics {
  std::map<std::string, double> sums;
  std::map<std::string, double> whole_sequence;  // metrics of the sequence itself (temporal_flicker)
  std::map<std::string, std::string> undefined;

  void add(int frame, bool several_frames, const MetricValues& values) {
    for (const auto& [name, value] : values.values) sums[name] += value;
    for (const auto& [name, why] : values.undefined) {
      if (!undefined.count(name)) undefined[name] = several_frames ? fmt::format("frame {}: {}", frame, why) : why;
    }
  }
  void add_sequence(const std::string& name, const MetricValue& value) {
    if (value.value)
      whole_sequence[name] = *value.value;
    else
      undefined[name] = value.undefined_reason;
  }
  nlohmann::json defined(size_t frame_count) const {
    nlohmann::json metrics = nlohmann::json::object();
    for (const auto& [name, sum] : sums) {
      if (undefined.count(name)) continue;
      metrics[name] = name == "nonfinite_pixels" ? sum : sum / static_cast<double>(frame_count);
    }
    for (const auto& [name, value] : whole_sequence) metrics[name] = value;
    return metrics;
  }
};

const FramePresence* find_frame(const std::vector<FramePresence>& frames, int frame) {
  for (const FramePresence& entry : frames)
    if (entry.frame == frame) return &entry;
  return nullptr;
}

// Measures one run from its share of a played sequence: metrics per frame against the reference,
// flicker over the sequence, timings per frame and over all frames and passes. `empty_reference` lists the
// frames whose reference has no caustic in view (an experiment with empty_reference_expected): those
// frames are not scored, and the record says so.
RunOutcome measure_run(const Experiment& experiment, const RunSpec& run, const CausticMethod& method,
                       const PrepareOutcome& prepare, SequenceOutput&& output, const VariantFrames& variant_frames,
                       const std::vector<FramePresence>& empty_reference) {
  RunOutcome outcome;
  nlohmann::json frames = nlohmann::json::array();
  std::vector<double> all_update, all_render, all_frame, all_gpu;
  RunMetrics run_metrics;
  std::vector<std::string> per_frame_metrics;
  for (const std::string& name : experiment.metrics) {
    if (find_metric(name).per_frame) per_frame_metrics.push_back(name);
  }
  const bool flicker = experiment.frames.size() > 1 && std::count(experiment.metrics.begin(), experiment.metrics.end(),
                                                                  std::string("temporal_flicker"));
  std::vector<Image> test_sequence, reference_sequence;
  std::vector<std::vector<uint8_t>> masks;
  size_t nonfinite = 0;
  for (size_t f = 0; f < experiment.frames.size(); ++f) {
    const int frame = experiment.frames[f];
    const PosedFrame& posed = *variant_frames.posed.at(frame);
    const FrameTimings& timings = output.timings[f];
    Image& image = output.images[f];
    for (size_t pass = 0; pass < timings.render_ms.size(); ++pass) {
      all_update.push_back(timings.update_ms[pass]);
      all_render.push_back(timings.render_ms[pass]);
      all_frame.push_back(timings.update_ms[pass] + timings.render_ms[pass]);
    }
    all_gpu.insert(all_gpu.end(), timings.gpu_render_ms.begin(), timings.gpu_render_ms.end());
    const Image& reference = variant_frames.reference.at(frame);
    MetricValues values = compute_metrics(image, reference, posed.gbuffer.receiver, per_frame_metrics);
    if (const FramePresence* empty = find_frame(empty_reference, frame)) mark_empty_reference(values, empty->presence);
    nonfinite += values.nonfinite_pixels;
    run_metrics.add(frame, experiment.frames.size() > 1, values);
    std::string file = ResultPaths::frame_file(frame) + ".exr";
    frames.push_back({{"frame", frame}, {"image", file}, {"update_ms", timings.update_ms}, {"render_ms", timings.render_ms},
                      {"metrics", values.values}});
    if (!values.undefined.empty()) frames.back()["metrics_undefined"] = values.undefined;
    if (!timings.gpu_render_ms.empty()) frames.back()["gpu_render_ms"] = timings.gpu_render_ms;
    if (flicker) {
      test_sequence.push_back(image);
      reference_sequence.push_back(reference);
      masks.push_back(posed.gbuffer.receiver);
    }
    outcome.images.push_back({frame, std::move(image)});
  }
  if (flicker) {
    MetricValue value = temporal_flicker(test_sequence, reference_sequence, masks);
    if (!empty_reference.empty())
      value = {std::nullopt, "empty reference: " + empty_reference.front().presence.describe()};
    run_metrics.add_sequence("temporal_flicker", value);
  }
  nlohmann::json counters = nlohmann::json::object();
  for (const auto& [name, value] : method.counters()) counters[name] = value;
  outcome.record = run_identity(experiment, run);
  outcome.record.update({{"status", nonfinite ? "failed" : "ok"},
                         {"error", nonfinite ? fmt::format("the output has {} non-finite pixels", nonfinite) : ""},
                         {"receiver_pixels", variant_frames.posed.at(experiment.frames.front())->gbuffer.receiver_count()},
                         {"frames", frames},
                         {"prepare_seconds", prepare.prepare_seconds},
                         {"prepare", prepare_json(prepare)},
                         {"timings", {{"update_ms_min", minimum(all_update)}, {"update_ms_median", median(all_update)},
                                      {"render_ms_min", minimum(all_render)}, {"render_ms_median", median(all_render)},
                                      {"frame_ms_min", minimum(all_frame)}, {"frame_ms_median", median(all_frame)}}},
                         {"metrics", run_metrics.defined(experiment.frames.size())},
                         {"memory_bytes", method.memory_bytes()},
                         {"peak_rss_bytes", peak_rss_bytes()},
                         {"counters", counters},
                         {"method_record", method.record()}});
  if (!run_metrics.undefined.empty()) outcome.record["metrics_undefined"] = run_metrics.undefined;
  if (!empty_reference.empty()) {
    nlohmann::json empty_frames_json = nlohmann::json::array();
    for (const FramePresence& entry : empty_reference) empty_frames_json.push_back(entry.frame);
    outcome.record["empty_reference"] = {{"frames", empty_frames_json},
                                         {"reason", empty_reference.front().presence.describe()}};
  }
  if (!all_gpu.empty()) {
    outcome.record["timings"]["gpu_render_ms_min"] = minimum(all_gpu);
    outcome.record["timings"]["gpu_render_ms_median"] = median(all_gpu);
  }
  return outcome;
}

void store_run(const ResultPaths& paths, const Experiment& experiment, const RunOutcome& outcome) {
  StagingFolder staging(paths.run(experiment.name, outcome.record["key"].get<std::string>()));
  for (const auto& [frame, image] : outcome.images) {
    write_exr(image, (fs::path(staging.path()) / (ResultPaths::frame_file(frame) + ".exr")).string());
  }
  write_text_atomically((fs::path(staging.path()) / "record.json").string(), outcome.record.dump(2) + "\n");
  staging.commit();
}

void store_failure(const ResultPaths& paths, const Experiment& experiment, const RunSpec& run, const std::string& error) {
  RunOutcome outcome;
  outcome.record = run_identity(experiment, run);
  outcome.record.update({{"status", "failed"},
                         {"error", error},
                         {"frames", nlohmann::json::array()},
                         {"metrics", nlohmann::json::object()}});
  store_run(paths, experiment, outcome);
}

}  // namespace

RunSummary run_experiment(const Experiment& experiment, const RunOptions& options) {
  ResultPaths paths{options.results};
  RunSummary summary;
  summary.total = experiment.runs.size();
  std::vector<const RunSpec*> pending;
  for (size_t i = 0; i < experiment.runs.size(); ++i) {
    const RunSpec& run = experiment.runs[i];
    if (static_cast<int>(i % options.shard_count) != options.shard_index) continue;
    if (!options.filter.empty() && !run_matches_filter(experiment, run, options.filter)) continue;
    ++summary.selected;
    bool stored = run_is_stored(paths.run(experiment.name, run.key));
    if (options.dry_run) {
      fmt::print("{}  {:<8} {}\n", run.key, stored && !options.force ? "stored" : "pending", run.label);
    }
    if (stored && !options.force) {
      ++summary.stored;
      continue;
    }
    pending.push_back(&run);
  }
  if (options.dry_run) return summary;

  // Every reference is computed (or loaded) and checked before any run starts, and before anything is
  // written into the experiment's folder: an empty reference stops here with nothing of it changed.
  ReferenceCheck references = check_references(experiment, pending, paths);

  std::string folder = paths.experiment(experiment.name);
  fs::create_directories(fs::path(folder) / "runs");
  remove_stale_staging((fs::path(folder) / "runs").string());
  nlohmann::json environment = environment_json(options.threads);
  environment["experiment"] = experiment.name;
  write_text_atomically((fs::path(folder) / "environment.json").string(), environment.dump(2) + "\n");
  write_text_atomically((fs::path(folder) / "experiment.json").string(), experiment.to_json().dump(2) + "\n");

  // Group pending runs by (variant, method, build knobs): prepare once per group (or load the build
  // from results/builds, which serves every variant, experiment and process); within a group, by
  // frame knobs: runs that differ only in render knobs share update().
  struct Group {
    std::vector<std::vector<const RunSpec*>> by_frame_knobs;
    std::map<std::string, size_t> index;
  };
  std::vector<Group> groups;
  std::map<std::string, size_t> group_of;
  for (const RunSpec* run : pending) {
    std::string group_key = std::to_string(run->variant) + "/" + run->method + run->build.to_json().dump();
    auto [it, inserted] = group_of.insert({group_key, groups.size()});
    if (inserted) groups.emplace_back();
    Group& group = groups[it->second];
    auto [sub, new_sub] = group.index.insert({run->frame.to_json().dump(), group.by_frame_knobs.size()});
    if (new_sub) group.by_frame_knobs.emplace_back();
    group.by_frame_knobs[sub->second].push_back(run);
  }
  // One variant after another, so that only one variant's frames are posed at a time.
  auto first_run = [](const Group& group) { return group.by_frame_knobs.front().front(); };
  std::stable_sort(groups.begin(), groups.end(),
                   [&](const Group& a, const Group& b) { return first_run(a)->variant < first_run(b)->variant; });
  const std::string build_cache = paths.builds();
  Progress progress(fmt::format("run {}", experiment.name), static_cast<double>(pending.size()));
  size_t done = 0;
  auto fail = [&](const RunSpec& run, const std::string& error) {
    store_failure(paths, experiment, run, error);
    ++summary.failed;
    fmt::print(stderr, "run {} failed: {}\n", run.label, error);
    progress.update(static_cast<double>(++done), run.label);
  };
  std::optional<size_t> current_variant;
  const std::vector<FramePresence> scored;  // no frame with an empty reference
  VariantFrames frames;
  std::unique_ptr<RestPose> rest;
  for (const Group& group : groups) {
    const RunSpec& first = *first_run(group);
    const SceneVariant& variant = experiment.variants.at(first.variant);
    if (current_variant != first.variant) {
      current_variant = first.variant;
      frames = VariantFrames{};
      rest.reset();
      if (references.kept_variant == first.variant) {
        frames = std::move(references.kept_frames);
        references.kept_variant.reset();
      } else {
        frames = variant_frames(experiment, variant, paths);  // stored by the check: loaded, not computed
      }
    }
    auto empty = references.empty.find(first.variant);
    const std::vector<FramePresence>& empty_reference = empty == references.empty.end() ? scored : empty->second;
    std::unique_ptr<CausticMethod> method = create_method(first.method);
    PrepareOutcome prepared;
    std::string prepare_error;
    try {
      auto zero = frames.posed.find(0);
      const PosedFrame* frame_zero = zero == frames.posed.end() ? nullptr : zero->second.get();
      prepared = prepare_method(*method, prepare_context(variant.scene, experiment.frames, frame_zero, rest), first.build,
                                build_cache);
      if (!prepared.build_key.empty()) {
        fmt::print(stderr, "build {} of {}: {} ({:.3g} s to compute{})\n", prepared.build_key, first.method, prepared.source,
                   prepared.prepare_seconds,
                   prepared.source == "loaded" ? fmt::format(", {:.3g} s to load", prepared.load_seconds) : "");
      }
    } catch (const std::exception& error) {
      prepare_error = error.what();
    }
    for (const std::vector<const RunSpec*>& runs : group.by_frame_knobs) {
      if (!prepare_error.empty()) {
        for (const RunSpec* run : runs) fail(*run, prepare_error);
        continue;
      }
      std::vector<ParamSet> render_sets;
      for (const RunSpec* run : runs) render_sets.push_back(run->render);
      std::vector<SequenceOutput> outputs;
      try {
        outputs = play_sequence(*method, frames.sequence(experiment.frames), runs.front()->frame, render_sets,
                                TimingProtocol{true, experiment.repetitions});
      } catch (const std::exception& error) {
        for (const RunSpec* run : runs) fail(*run, error.what());
        continue;
      }
      for (size_t r = 0; r < runs.size(); ++r) {
        const RunSpec& run = *runs[r];
        try {
          RunOutcome outcome =
              measure_run(experiment, run, *method, prepared, std::move(outputs[r]), frames, empty_reference);
          store_run(paths, experiment, outcome);
          if (outcome.record["status"] == "ok") {
            ++summary.completed;
          } else {
            ++summary.failed;
            fmt::print(stderr, "run {} failed: {}\n", run.label, outcome.record["error"].get<std::string>());
          }
          progress.update(static_cast<double>(++done), run.label);
        } catch (const std::exception& error) {
          fail(run, error.what());
        }
      }
    }
  }
  progress.finish(fmt::format("{} runs, {} failed", done, summary.failed));
  return summary;
}

}  // namespace causticbench
