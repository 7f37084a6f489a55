#include "experiments/runner.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>

#include <fmt/format.h>

#include "core/files.h"
#include "core/image_statistics.h"
#include "core/progress.h"
#include "experiments/result_store.h"
#include "methods/method_runner.h"
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

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

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

// One posed frame with its tracer and G-buffer.
struct PosedFrame {
  SceneFrame frame;
  Tracer tracer;
  GBuffer gbuffer;
  PosedFrame(const Scene& scene, int index) : frame(scene, index), tracer(frame), gbuffer(render_gbuffer(tracer)) {}
};

// The frames of one scene variant, posed once and shared by its reference and all its runs (methods
// take them by const reference), with the reference's E_c of each.
struct VariantFrames {
  std::map<int, std::unique_ptr<PosedFrame>> posed;
  std::map<int, Image> reference;
};

// Poses the variant's frames and loads each cached reference frame, or computes and stores it; then
// rewrites the reference folder's record.json summary if a frame was computed.
VariantFrames variant_frames(const Experiment& experiment, const SceneVariant& variant, const ResultPaths& paths) {
  VariantFrames frames;
  fs::path folder = paths.reference(variant.reference_key);
  fs::create_directories(folder);
  bool computed = false;
  for (int frame : experiment.frames) {
    const PosedFrame& posed = *(frames.posed[frame] = std::make_unique<PosedFrame>(variant.scene, frame));
    fs::path image = folder / (ResultPaths::frame_file(frame) + ".exr");
    fs::path record = folder / (ResultPaths::frame_file(frame, "record") + ".json");
    if (fs::is_regular_file(record) && fs::is_regular_file(image)) {
      frames.reference[frame] = read_exr(image.string());
      continue;
    }
    fmt::print(stderr, "reference {} frame {}{}: computing (cached in {})\n", variant.reference_key, frame,
               experiment.variants.size() > 1 ? " of variant " + variant.name : "", folder.string());
    std::unique_ptr<CausticMethod> method = create_method("reference");
    const MethodInfo& info = method->info();
    method->prepare(variant.scene, select_phase(experiment.reference_params, info.params, ParamPhase::build));
    method->update(FrameContext{posed.frame, posed.tracer});
    Image caustic = method->render(posed.gbuffer, select_phase(experiment.reference_params, info.params, ParamPhase::render));
    posed.gbuffer.clear_outside_receivers(caustic);
    write_exr(caustic, image.string());
    write_exr(posed.gbuffer.to_image(), (folder / (ResultPaths::frame_file(frame, "gbuffer") + ".exr")).string());
    nlohmann::json frame_record = method->record();
    frame_record["frame"] = frame;
    frame_record["params"] = experiment.reference_params.to_json();
    write_text_atomically(record.string(), frame_record.dump(2) + "\n");
    frames.reference[frame] = std::move(caustic);
    computed = true;
  }
  if (!computed) return frames;
  // record.json summarises every stored frame (of this and earlier experiments); its top level is the
  // first frame's record.
  nlohmann::json summary = nlohmann::json::object(), stored_frames = nlohmann::json::object();
  int first = -1;
  for (const auto& entry : fs::directory_iterator(folder)) {
    std::string file = entry.path().filename().string();
    if (file.rfind("record_", 0) != 0) continue;
    std::ifstream stream(entry.path());
    nlohmann::json stored = nlohmann::json::parse(stream);
    int index = stored["frame"].get<int>();
    stored_frames[std::to_string(index)] = {{"noise_floor", stored["noise_floor"]}, {"passes", stored["passes"]},
                                            {"seconds", stored["seconds"]}, {"stop_reason", stored["stop_reason"]}};
    if (first < 0 || index < first) {
      first = index;
      summary = stored;
    }
  }
  summary["frames"] = stored_frames;
  summary["key"] = variant.reference_key;
  write_text_atomically((folder / "record.json").string(), summary.dump(2) + "\n");
  return frames;
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
          {"render", run.render.to_json()},
          {"swept", run.swept},
          {"spec", run.spec}};
}

struct RunOutcome {
  nlohmann::json record;
  std::vector<std::pair<int, Image>> images;
};

// Times and measures one run whose method has been prepared.
RunOutcome measure_run(const Experiment& experiment, const RunSpec& run, CausticMethod& method, double prepare_seconds,
                       const VariantFrames& variant_frames) {
  RunOutcome outcome;
  nlohmann::json frames = nlohmann::json::array();
  std::vector<double> all_update, all_render, all_frame, all_gpu;
  std::map<std::string, double> metric_sums;
  std::vector<std::string> per_frame_metrics;
  for (const std::string& name : experiment.metrics) {
    if (find_metric(name).per_frame) per_frame_metrics.push_back(name);
  }
  const bool flicker = experiment.frames.size() > 1 && std::count(experiment.metrics.begin(), experiment.metrics.end(),
                                                                  std::string("temporal_flicker"));
  std::vector<Image> test_sequence, reference_sequence;
  std::vector<std::vector<uint8_t>> masks;
  size_t nonfinite = 0;
  for (int frame : experiment.frames) {
    const PosedFrame& posed = *variant_frames.posed.at(frame);
    FrameContext context{posed.frame, posed.tracer};
    Image image;
    // One warm-up, then the timed repetitions.
    method.update(context);
    image = method.render(posed.gbuffer, run.render);
    std::vector<double> update_ms, render_ms, gpu_ms;
    for (int repetition = 0; repetition < experiment.repetitions; ++repetition) {
      auto start = Clock::now();
      method.update(context);
      update_ms.push_back(seconds_since(start) * 1e3);
      start = Clock::now();
      image = method.render(posed.gbuffer, run.render);
      render_ms.push_back(seconds_since(start) * 1e3);
      // GPU backends report their kernel time from timestamp queries.
      nlohmann::json facts = method.record();
      if (facts.contains("gpu_render_ms") && facts["gpu_render_ms"].get<double>() > 0.0) {
        gpu_ms.push_back(facts["gpu_render_ms"].get<double>());
        all_gpu.push_back(gpu_ms.back());
      }
      all_update.push_back(update_ms.back());
      all_render.push_back(render_ms.back());
      all_frame.push_back(update_ms.back() + render_ms.back());
    }
    posed.gbuffer.clear_outside_receivers(image);
    const Image& reference = variant_frames.reference.at(frame);
    MetricValues values = compute_metrics(image, reference, posed.gbuffer.receiver, per_frame_metrics);
    nonfinite += values.nonfinite_pixels;
    for (const auto& [name, value] : values.values) metric_sums[name] += value;
    std::string file = ResultPaths::frame_file(frame) + ".exr";
    frames.push_back({{"frame", frame}, {"image", file}, {"update_ms", update_ms}, {"render_ms", render_ms},
                      {"metrics", values.values}});
    if (!gpu_ms.empty()) frames.back()["gpu_render_ms"] = gpu_ms;
    if (flicker) {
      test_sequence.push_back(image);
      reference_sequence.push_back(reference);
      masks.push_back(posed.gbuffer.receiver);
    }
    outcome.images.push_back({frame, std::move(image)});
  }
  nlohmann::json metrics = nlohmann::json::object();
  for (const auto& [name, sum] : metric_sums) {
    metrics[name] = name == "nonfinite_pixels" ? sum : sum / static_cast<double>(experiment.frames.size());
  }
  if (flicker) metrics["temporal_flicker"] = temporal_flicker(test_sequence, reference_sequence, masks);
  nlohmann::json counters = nlohmann::json::object();
  for (const auto& [name, value] : method.counters()) counters[name] = value;
  outcome.record = run_identity(experiment, run);
  outcome.record.update({{"status", nonfinite ? "failed" : "ok"},
                         {"error", nonfinite ? fmt::format("the output has {} non-finite pixels", nonfinite) : ""},
                         {"receiver_pixels", variant_frames.posed.at(experiment.frames.front())->gbuffer.receiver_count()},
                         {"frames", frames},
                         {"prepare_seconds", prepare_seconds},
                         {"timings", {{"update_ms_min", minimum(all_update)}, {"update_ms_median", median(all_update)},
                                      {"render_ms_min", minimum(all_render)}, {"render_ms_median", median(all_render)},
                                      {"frame_ms_min", minimum(all_frame)}, {"frame_ms_median", median(all_frame)}}},
                         {"metrics", metrics},
                         {"memory_bytes", method.memory_bytes()},
                         {"peak_rss_bytes", peak_rss_bytes()},
                         {"counters", counters},
                         {"method_record", method.record()}});
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

  std::string folder = paths.experiment(experiment.name);
  fs::create_directories(fs::path(folder) / "runs");
  remove_stale_staging((fs::path(folder) / "runs").string());
  nlohmann::json environment = environment_json(options.threads);
  environment["experiment"] = experiment.name;
  write_text_atomically((fs::path(folder) / "environment.json").string(), environment.dump(2) + "\n");
  write_text_atomically((fs::path(folder) / "experiment.json").string(), experiment.to_json().dump(2) + "\n");

  // Group pending runs by (variant, method, build knobs): prepare once per group.
  std::vector<std::vector<const RunSpec*>> groups;
  std::map<std::string, size_t> group_of;
  for (const RunSpec* run : pending) {
    std::string group_key = std::to_string(run->variant) + "/" + run->method + run->build.to_json().dump();
    auto [it, inserted] = group_of.insert({group_key, groups.size()});
    if (inserted) groups.emplace_back();
    groups[it->second].push_back(run);
  }
  // One variant after another, so that only one variant's frames are posed at a time.
  std::stable_sort(groups.begin(), groups.end(), [](const auto& a, const auto& b) { return a.front()->variant < b.front()->variant; });
  Progress progress(fmt::format("run {}", experiment.name), static_cast<double>(pending.size()));
  size_t done = 0;
  std::optional<size_t> current_variant;
  VariantFrames frames;
  for (const auto& group : groups) {
    if (current_variant != group.front()->variant) {
      current_variant = group.front()->variant;
      frames = VariantFrames{};
      frames = variant_frames(experiment, experiment.variants[*current_variant], paths);
    }
    std::unique_ptr<CausticMethod> method = create_method(group.front()->method);
    double prepare_seconds = 0.0;
    std::string prepare_error;
    try {
      const Scene& scene = experiment.variants.at(group.front()->variant).scene;
      method->check_scene(scene);
      auto start = Clock::now();
      method->prepare(scene, group.front()->build);
      prepare_seconds = seconds_since(start);
    } catch (const std::exception& error) {
      prepare_error = error.what();
    }
    for (const RunSpec* run : group) {
      try {
        if (!prepare_error.empty()) throw std::runtime_error(prepare_error);
        RunOutcome outcome = measure_run(experiment, *run, *method, prepare_seconds, frames);
        store_run(paths, experiment, outcome);
        if (outcome.record["status"] == "ok") {
          ++summary.completed;
        } else {
          ++summary.failed;
          fmt::print(stderr, "run {} failed: {}\n", run->label, outcome.record["error"].get<std::string>());
        }
      } catch (const std::exception& error) {
        store_failure(paths, experiment, *run, error.what());
        ++summary.failed;
        fmt::print(stderr, "run {} failed: {}\n", run->label, error.what());
      }
      progress.update(static_cast<double>(++done), run->label);
    }
  }
  progress.finish(fmt::format("{} runs, {} failed", done, summary.failed));
  return summary;
}

}  // namespace causticbench
