// The record of a measured run (experiments/run_record.h).
#include "experiments/run_record.h"

#include <sys/resource.h>

#include <algorithm>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "experiments/result_store.h"
#include "metrics/metrics.h"

namespace causticbench {

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

}  // namespace

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
    if (!values.parameters.empty()) frames.back()["metric_parameters"] = values.parameters;
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
  outcome.record.update(reference_fields(variant_frames, experiment.frames));
  return outcome;
}

}  // namespace causticbench
