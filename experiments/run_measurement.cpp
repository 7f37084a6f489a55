// Measuring a run (declared in run_measurement.h).
#include "experiments/run_measurement.h"

#include <sys/resource.h>

#include <algorithm>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "core/build_info.h"
#include "store/result_paths.h"
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

// A frame whose reference is empty is not scored: every metric of it is undefined, except the two that
// judge the method alone: the count of non-finite pixels, and max_error, which against an empty reference
// is the brightest E_c the method put where there is none (0 when it, too, gave nothing: the extremes
// studies' "nothing where nothing is").
void mark_empty_reference(MetricValues& values, const std::string& reason) {
  for (auto it = values.values.begin(); it != values.values.end();) {
    if (it->first == "nonfinite_pixels" || it->first == "max_error") {
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
  std::map<std::string, double> defined(size_t frame_count) const {
    std::map<std::string, double> metrics;
    for (const auto& [name, sum] : sums) {
      if (undefined.count(name)) continue;
      metrics[name] = name == "nonfinite_pixels" ? sum : sum / static_cast<double>(frame_count);
    }
    for (const auto& [name, value] : whole_sequence) metrics[name] = value;
    return metrics;
  }
};

FrameRecord& frame_of(RunRecord& record, int frame) {
  for (FrameRecord& entry : record.frames)
    if (entry.frame == frame) return entry;
  record.frames.push_back(FrameRecord{});
  record.frames.back().frame = frame;
  return record.frames.back();
}

}  // namespace

RunRecord run_identity(const Experiment& experiment, const RunSpec& run) {
  const SceneVariant& variant = experiment.variants.at(run.variant);
  RunRecord record;
  record.key = run.key;
  record.method = run.method;
  record.label = run.label;
  record.entry = run.entry;
  record.variant = variant.name;
  record.reference_key = variant.reference_key;
  record.git_revision = git_revision();
  record.reference_settings = experiment.reference_params.to_json();
  record.build = run.build.to_json();
  record.frame = run.frame.to_json();
  record.render = run.render.to_json();
  record.swept = run.swept;
  record.spec = run.spec;
  return record;
}

size_t score_run(RunRecord& record, const std::vector<std::string>& metrics, const std::vector<ScoredFrame>& frames) {
  std::vector<std::string> per_frame;
  for (const std::string& name : metrics)
    if (find_metric(name).per_frame) per_frame.push_back(name);
  const bool several = frames.size() > 1;
  const bool flicker = several && std::count(metrics.begin(), metrics.end(), std::string("temporal_flicker"));
  RunMetrics run_metrics;
  size_t nonfinite = 0;
  std::vector<Image> tests, references;
  std::vector<std::vector<uint8_t>> masks;
  std::optional<std::string> empty;
  for (const ScoredFrame& scored : frames) {
    MetricValues values = compute_metrics(*scored.test, *scored.reference, *scored.mask, per_frame);
    if (scored.empty_reference) {
      mark_empty_reference(values, *scored.empty_reference);
      if (!empty) empty = *scored.empty_reference;
    }
    nonfinite += values.nonfinite_pixels;
    run_metrics.add(scored.frame, several, values);
    FrameRecord& frame = frame_of(record, scored.frame);
    frame.metrics = values.values;
    frame.metrics_undefined = values.undefined;
    frame.metric_parameters = values.parameters;
    if (flicker) {
      tests.push_back(*scored.test);
      references.push_back(*scored.reference);
      masks.push_back(*scored.mask);
    }
  }
  if (flicker) {
    MetricValue value = temporal_flicker(tests, references, masks);
    if (empty) value = {std::nullopt, *empty};
    run_metrics.add_sequence("temporal_flicker", value);
  }
  record.metrics = run_metrics.defined(frames.size());
  record.metrics_undefined = run_metrics.undefined;
  return nonfinite;
}

RunOutcome measure_run(const Experiment& experiment, const RunSpec& run, const CausticMethod& method,
                       const PrepareOutcome& prepare, SequenceOutput&& output, const VariantFrames& variant_frames,
                       const std::vector<FramePresence>& empty_reference) {
  RunOutcome outcome;
  RunRecord& record = outcome.record;
  record = run_identity(experiment, run);
  std::vector<double> all_update, all_render, all_frame, all_gpu;
  std::vector<ScoredFrame> scored;
  for (size_t f = 0; f < experiment.frames.size(); ++f) {
    const int frame = experiment.frames[f];
    const FrameTimings& timings = output.timings[f];
    for (size_t pass = 0; pass < timings.render_ms.size(); ++pass) {
      all_update.push_back(timings.update_ms[pass]);
      all_render.push_back(timings.render_ms[pass]);
      all_frame.push_back(timings.update_ms[pass] + timings.render_ms[pass]);
    }
    all_gpu.insert(all_gpu.end(), timings.gpu_render_ms.begin(), timings.gpu_render_ms.end());
    FrameRecord entry;
    entry.frame = frame;
    entry.image = ResultPaths::frame_file(frame) + ".exr";
    entry.update_ms = timings.update_ms;
    entry.render_ms = timings.render_ms;
    entry.gpu_render_ms = timings.gpu_render_ms;
    record.frames.push_back(entry);
    ScoredFrame one{frame, &output.images[f], &variant_frames.reference.at(frame),
                    &variant_frames.posed.at(frame)->gbuffer.receiver, std::nullopt};
    for (const FramePresence& empty : empty_reference)
      if (empty.frame == frame) one.empty_reference = "empty reference: " + empty.presence.describe();
    scored.push_back(one);
  }
  const size_t nonfinite = score_run(record, experiment.metrics, scored);
  for (size_t f = 0; f < experiment.frames.size(); ++f) outcome.images.push_back({experiment.frames[f], std::move(output.images[f])});

  record.status = nonfinite ? "failed" : "ok";
  record.error = nonfinite ? fmt::format("the output has {} non-finite pixels", nonfinite) : "";
  record.receiver_pixels =
      static_cast<int64_t>(variant_frames.posed.at(experiment.frames.front())->gbuffer.receiver_count());
  record.prepare = {prepare.source, prepare.build_key, prepare.prepare_seconds, prepare.load_seconds,
                    prepare.save_seconds, prepare.warning};
  record.timings.update_ms_min = minimum(all_update);
  record.timings.update_ms_median = median(all_update);
  record.timings.render_ms_min = minimum(all_render);
  record.timings.render_ms_median = median(all_render);
  record.timings.frame_ms_min = minimum(all_frame);
  record.timings.frame_ms_median = median(all_frame);
  if (!all_gpu.empty()) {
    record.timings.gpu_render_ms_min = minimum(all_gpu);
    record.timings.gpu_render_ms_median = median(all_gpu);
  }
  // This run's own (SequenceOutput), not what the shared instance holds after the group's last run.
  record.memory_bytes = static_cast<int64_t>(output.memory_bytes);
  record.peak_rss_bytes = static_cast<int64_t>(peak_rss_bytes());
  for (const auto& [name, value] : output.counters) record.counters[name] = value;
  record.method_record = output.method_record;
  record.lost_flux = lost_flux_record(output.lost_flux);
  if (!empty_reference.empty()) {
    std::vector<int> frames;
    for (const FramePresence& entry : empty_reference) frames.push_back(entry.frame);
    record.empty_reference_frames = frames;
    record.empty_reference_reason = empty_reference.front().presence.describe();
  }
  const nlohmann::json reference = reference_fields(variant_frames, experiment.frames);
  record.reference_images = reference["reference_images"];
  record.reference_converged = reference["reference_converged"].get<bool>();
  if (reference.contains("reference_unconverged")) record.reference_unconverged = reference["reference_unconverged"];
  return outcome;
}

}  // namespace causticbench
