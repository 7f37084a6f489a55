// The run record's JSON form (declared in run_record.h; the fields: docs/results-format.md).
#include "store/run_record.h"

#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "methods/quantity_registry.h"

namespace causticbench {

namespace {

using nlohmann::json;

// Reads the fields of one JSON object, naming the first one that is missing or of another type.
class FieldReader {
 public:
  FieldReader(const json& object, std::string where) : object_(object), where_(std::move(where)) {
    if (!object_.is_object()) throw RecordError(fmt::format("{}is {}, not a JSON object", prefix(), object_.type_name()));
  }
  bool has(const char* name) const { return object_.contains(name) && !object_[name].is_null(); }
  const json& at(const char* name) const {
    if (!object_.contains(name)) throw RecordError(fmt::format("{}field '{}' is missing", prefix(), name));
    return object_[name];
  }
  std::string string(const char* name) const { return typed(name, at(name), &json::is_string, "a string"); }
  std::string string_or(const char* name, const std::string& fallback) const { return has(name) ? string(name) : fallback; }
  double number(const char* name) const { return typed(name, at(name), &json::is_number, "a number"); }
  double number_or(const char* name, double fallback) const { return has(name) ? number(name) : fallback; }
  int64_t integer(const char* name) const { return typed(name, at(name), &json::is_number_integer, "an integer"); }
  const json& object(const char* name) const { return checked(name, at(name), &json::is_object, "an object"); }
  const json& array(const char* name) const { return checked(name, at(name), &json::is_array, "an array"); }
  json object_or_empty(const char* name) const { return has(name) ? object(name) : json::object(); }
  json any_or_null(const char* name) const { return object_.contains(name) ? object_[name] : json(); }
  std::vector<double> numbers_or_empty(const char* name) const {
    std::vector<double> values;
    if (!has(name)) return values;
    for (const json& value : array(name)) values.push_back(number_value(name, value));
    return values;
  }
  std::map<std::string, double> number_map(const char* name) const {
    std::map<std::string, double> values;
    if (!has(name)) return values;
    for (const auto& [key, value] : object(name).items()) values[key] = number_value(name, value);
    return values;
  }
  std::map<std::string, std::string> text_map(const char* name) const {
    std::map<std::string, std::string> values;
    if (!has(name)) return values;
    for (const auto& [key, value] : object(name).items()) {
      if (!value.is_string()) throw type_error(name, value, "an object of strings");
      values[key] = value.get<std::string>();
    }
    return values;
  }
  std::string prefix() const { return where_.empty() ? "" : where_ + ": "; }

 private:
  // A number, or null for a value JSON cannot hold (+inf, NaN), read as NaN.
  double number_value(const char* name, const json& value) const {
    if (value.is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!value.is_number()) throw type_error(name, value, "numbers");
    return value.get<double>();
  }
  RecordError type_error(const char* name, const json& value, const char* expected) const {
    return RecordError(fmt::format("{}field '{}' holds {}, expected {}", prefix(), name, value.type_name(), expected));
  }
  const json& checked(const char* name, const json& value, bool (json::*test)() const noexcept, const char* expected) const {
    if (!(value.*test)()) throw type_error(name, value, expected);
    return value;
  }
  // The checked value, converted to what the caller assigns it to.
  struct Any {
    const json& value;
    operator std::string() const { return value.get<std::string>(); }
    operator double() const { return value.get<double>(); }
    operator int64_t() const { return value.get<int64_t>(); }
  };
  Any typed(const char* name, const json& value, bool (json::*test)() const noexcept, const char* expected) const {
    return Any{checked(name, value, test, expected)};
  }

  const json& object_;
  std::string where_;
};

FrameRecord read_frame(const json& stored, size_t index) {
  FieldReader in(stored, fmt::format("frames[{}]", index));
  FrameRecord frame;
  frame.frame = static_cast<int>(in.integer("frame"));
  frame.image = in.string("image");
  frame.update_ms = in.numbers_or_empty("update_ms");
  frame.render_ms = in.numbers_or_empty("render_ms");
  frame.gpu_render_ms = in.numbers_or_empty("gpu_render_ms");
  frame.metrics = in.number_map("metrics");
  frame.metrics_undefined = in.text_map("metrics_undefined");
  if (in.has("metric_parameters")) {
    for (const auto& [metric, parameters] : in.object("metric_parameters").items())
      frame.metric_parameters[metric] = FieldReader(in.object("metric_parameters"), in.prefix() + "metric_parameters")
                                            .number_map(metric.c_str());
  }
  return frame;
}

json frame_json(const FrameRecord& frame) {
  json out = {{"frame", frame.frame},
              {"image", frame.image},
              {"update_ms", frame.update_ms},
              {"render_ms", frame.render_ms},
              {"metrics", frame.metrics}};
  if (!frame.gpu_render_ms.empty()) out["gpu_render_ms"] = frame.gpu_render_ms;
  if (!frame.metrics_undefined.empty()) out["metrics_undefined"] = frame.metrics_undefined;
  if (!frame.metric_parameters.empty()) out["metric_parameters"] = frame.metric_parameters;
  return out;
}

SeedsRecord read_seeds(const json& stored) {
  FieldReader in(stored, "seeds");
  SeedsRecord seeds;
  const json& runs = in.array("runs");
  if (runs.empty()) throw RecordError("seeds: field 'runs' is empty");
  for (size_t r = 0; r < runs.size(); ++r) {
    FieldReader run(runs[r], fmt::format("seeds.runs[{}]", r));
    SeedRun one;
    one.seed = run.integer("seed");
    const json& frames = run.array("frames");
    for (size_t f = 0; f < frames.size(); ++f) one.frames.push_back(read_frame(frames[f], f));
    one.metrics = run.number_map("metrics");
    one.metrics_undefined = run.text_map("metrics_undefined");
    seeds.runs.push_back(std::move(one));
  }
  if (in.has("intervals")) {
    for (const auto& [name, value] : in.object("intervals").items()) {
      FieldReader interval(value, "seeds.intervals." + name);
      seeds.intervals[name] = MetricInterval{interval.number("mean"), interval.number("half_width"),
                                             interval.number("standard_deviation"),
                                             static_cast<int>(interval.integer("count"))};
    }
  }
  if (in.has("stddev_images")) {
    for (const json& image : in.array("stddev_images")) {
      if (!image.is_string()) throw RecordError("seeds: field 'stddev_images' holds a non-string");
      seeds.stddev_images.push_back(image.get<std::string>());
    }
  }
  return seeds;
}

json seeds_json(const SeedsRecord& seeds) {
  json runs = json::array();
  for (const SeedRun& run : seeds.runs) {
    json frames = json::array();
    for (const FrameRecord& frame : run.frames) frames.push_back(frame_json(frame));
    json one = {{"seed", run.seed}, {"frames", frames}, {"metrics", run.metrics}};
    if (!run.metrics_undefined.empty()) one["metrics_undefined"] = run.metrics_undefined;
    runs.push_back(one);
  }
  json intervals = json::object();
  for (const auto& [name, interval] : seeds.intervals)
    intervals[name] = {{"mean", interval.mean},
                       {"half_width", interval.half_width},
                       {"standard_deviation", interval.standard_deviation},
                       {"count", interval.count}};
  return {{"count", seeds.runs.size()},
          {"confidence", kIntervalConfidence},
          {"runs", runs},
          {"intervals", intervals},
          {"stddev_images", seeds.stddev_images}};
}

}  // namespace

std::optional<LostFluxRecord> lost_flux_record(const std::vector<std::optional<LostFlux>>& frames) {
  const std::optional<LostFlux>* worst = nullptr;
  for (const std::optional<LostFlux>& frame : frames)
    if (frame && (!worst || frame->fraction > (*worst)->fraction)) worst = &frame;
  if (!worst) return std::nullopt;
  LostFluxRecord record{**worst, {}, {}};
  bool moved = false;
  for (const std::optional<LostFlux>& frame : frames) {
    record.frames.push_back(frame ? frame->fraction : std::numeric_limits<double>::quiet_NaN());
    moved = moved || (frame && frame->moved != 0.0);
  }
  if (moved)
    for (const std::optional<LostFlux>& frame : frames)
      record.moved_frames.push_back(frame ? frame->moved : std::numeric_limits<double>::quiet_NaN());
  return record;
}

std::optional<double> RunTimings::field(const std::string& name) const {
  if (name == "update_ms_min") return update_ms_min;
  if (name == "update_ms_median") return update_ms_median;
  if (name == "render_ms_min") return render_ms_min;
  if (name == "render_ms_median") return render_ms_median;
  if (name == "frame_ms_min") return frame_ms_min;
  if (name == "frame_ms_median") return frame_ms_median;
  if (name == "gpu_render_ms_min") return gpu_render_ms_min;
  if (name == "gpu_render_ms_median") return gpu_render_ms_median;
  return std::nullopt;
}

int stored_seed_count(const json& stored) {
  if (!stored.is_object() || stored.value("status", "") != "ok") return std::numeric_limits<int>::max();
  if (!stored.contains("seeds") || !stored["seeds"].is_object()) return 1;
  const json& runs = stored["seeds"].value("runs", json::array());
  return runs.is_array() ? static_cast<int>(runs.size()) : 1;
}

bool stored_with_fewer_seeds(const json& stored, int seeds) {
  if (seeds <= 1 || stored_seed_count(stored) >= seeds) return false;
  for (const char* phase : {"build", "frame", "render"})
    if (stored.contains(phase) && stored[phase].is_object() && stored[phase].contains("seed")) return true;
  return false;
}

int stored_record_version(const json& stored) {
  if (!stored.is_object() || !stored.contains("record_version")) return 1;
  const json& version = stored["record_version"];
  if (!version.is_number_integer()) throw RecordError("field 'record_version' is not an integer");
  return version.get<int>();
}

json upgrade_run_record(json stored) {
  if (!stored.is_object()) throw RecordError(fmt::format("it is {}, not a JSON object", stored.type_name()));
  const int version = stored_record_version(stored);
  if (version > kRunRecordVersion) {
    throw RecordError(fmt::format(
        "it is a record of version {}, written by a newer causticbench; this one reads versions 1 to {}: report it "
        "with the causticbench that wrote it, or run the experiment again",
        version, kRunRecordVersion));
  }
  if (version < 1) throw RecordError(fmt::format("its record_version is {}, expected 1 to {}", version, kRunRecordVersion));
  if (version == 1) {
    // Version 1 said nothing of the build that measured it or the reference's settings.
    stored["record_version"] = 2;
    stored["git_revision"] = "";
    stored["reference_settings"] = nullptr;
  }
  return stored;
}

std::string entry_of_label(const std::string& label, const std::string& variant, const json& swept) {
  std::string entry = label;
  const std::string at = " @" + variant;
  if (!variant.empty() && entry.size() > at.size() && entry.ends_with(at)) entry.resize(entry.size() - at.size());
  // The swept words were appended in the entry's order, not the record's: strip each of them once, from
  // the end, whichever comes last (an entry label may itself end in a word like one of them).
  std::set<std::string> words;
  if (swept.is_object())
    for (const auto& [name, value] : swept.items())
      words.insert(" " + name + "=" + (value.is_string() ? value.get<std::string>() : value.dump()));
  bool stripped = true;
  while (stripped && !words.empty()) {
    stripped = false;
    for (auto word = words.begin(); word != words.end(); ++word) {
      if (entry.size() > word->size() && entry.ends_with(*word)) {
        entry.resize(entry.size() - word->size());
        words.erase(word);
        stripped = true;
        break;
      }
    }
  }
  return entry;
}

RunRecord RunRecord::from_json(const json& original) {
  const json stored = upgrade_run_record(original);
  FieldReader in(stored, "");
  RunRecord record;
  record.record_version = static_cast<int>(in.integer("record_version"));
  record.key = in.string("key");
  record.status = in.string("status");
  record.error = in.string("error");
  record.method = in.string("method");
  record.label = in.string("label");
  if (record.status != "ok" && record.status != "failed")
    throw RecordError(fmt::format("its status is '{}', expected ok or failed", record.status));
  record.variant = in.string_or("variant", "");
  record.reference_key = in.string_or("reference_key", "");
  record.git_revision = in.string_or("git_revision", "");
  record.reference_settings = in.any_or_null("reference_settings");
  record.build = in.object_or_empty("build");
  record.frame = in.object_or_empty("frame");
  record.render = in.object_or_empty("render");
  record.swept = in.object_or_empty("swept");
  record.entry = in.string_or("entry", entry_of_label(record.label, record.variant, record.swept));
  record.spec = in.any_or_null("spec");
  if (in.has("receiver_pixels")) record.receiver_pixels = in.integer("receiver_pixels");
  // A failed run has only its identity and error, unless it failed after measuring (non-finite pixels).
  if (!record.ok() && (!in.has("frames") || in.at("frames").empty())) return record;

  const json& frames = in.array("frames");
  if (frames.empty()) throw RecordError("an ok record with no frame");
  for (size_t i = 0; i < frames.size(); ++i) record.frames.push_back(read_frame(frames[i], i));
  FieldReader timings(in.object("timings"), "timings");
  for (auto [name, target] : {std::pair{"update_ms_min", &record.timings.update_ms_min},
                              {"update_ms_median", &record.timings.update_ms_median},
                              {"render_ms_min", &record.timings.render_ms_min},
                              {"render_ms_median", &record.timings.render_ms_median},
                              {"frame_ms_min", &record.timings.frame_ms_min},
                              {"frame_ms_median", &record.timings.frame_ms_median}})
    *target = timings.number_or(name, 0.0);
  if (timings.has("gpu_render_ms_min")) record.timings.gpu_render_ms_min = timings.number("gpu_render_ms_min");
  if (timings.has("gpu_render_ms_median")) record.timings.gpu_render_ms_median = timings.number("gpu_render_ms_median");
  in.object("metrics");
  record.metrics = in.number_map("metrics");
  record.metrics_undefined = in.text_map("metrics_undefined");
  if (in.has("prepare")) {
    FieldReader prepare(in.object("prepare"), "prepare");
    record.prepare.source = prepare.string_or("source", "computed");
    record.prepare.build_key = prepare.string_or("build_key", "");
    record.prepare.prepare_seconds = prepare.number_or("prepare_seconds", in.number_or("prepare_seconds", 0.0));
    record.prepare.load_seconds = prepare.number_or("load_seconds", 0.0);
    record.prepare.save_seconds = prepare.number_or("save_seconds", 0.0);
    record.prepare.warning = prepare.string_or("warning", "");
  } else {
    record.prepare.prepare_seconds = in.number_or("prepare_seconds", 0.0);
  }
  if (in.has("empty_reference")) {
    FieldReader empty(in.object("empty_reference"), "empty_reference");
    std::vector<int> frames_without;
    for (double frame : empty.numbers_or_empty("frames")) frames_without.push_back(static_cast<int>(frame));
    record.empty_reference_frames = frames_without;
    record.empty_reference_reason = empty.string_or("reason", "");
  }
  record.memory_bytes = static_cast<int64_t>(in.number_or("memory_bytes", 0.0));
  record.peak_rss_bytes = static_cast<int64_t>(in.number_or("peak_rss_bytes", 0.0));
  record.counters = in.number_map("counters");
  record.method_record = in.has("method_record") ? in.at("method_record") : json::object();
  if (in.has("lost_flux")) {
    FieldReader lost(in.object("lost_flux"), "lost_flux");
    record.lost_flux = LostFluxRecord{
        LostFlux{lost.number("fraction"), lost.string_or("what", ""), lost.string_or("knob", ""),
                 lost.string_or("advice", ""), lost.number_or("moved", 0.0)},
        lost.numbers_or_empty("frames"), lost.numbers_or_empty("moved_frames")};
  }
  record.images = in.any_or_null("images");
  record.reference_images = in.any_or_null("reference_images");
  if (in.has("reference_converged")) {
    const json& converged = in.at("reference_converged");
    if (!converged.is_boolean()) throw RecordError("field 'reference_converged' is not true or false");
    record.reference_converged = converged.get<bool>();
  }
  record.reference_unconverged = in.string_or("reference_unconverged", "");
  if (in.has("seeds")) record.seeds = read_seeds(in.at("seeds"));
  return record;
}

json RunRecord::to_json() const {
  json out = {{"record_version", record_version},
              {"key", key},
              {"status", status},
              {"error", error},
              {"method", method},
              {"label", label},
              {"entry", entry},
              {"variant", variant},
              {"reference_key", reference_key},
              {"git_revision", git_revision},
              {"reference_settings", reference_settings},
              {"build", build},
              {"frame", frame},
              {"render", render},
              {"swept", swept},
              {"spec", spec}};
  if (receiver_pixels) out["receiver_pixels"] = *receiver_pixels;
  if (!ok() && frames.empty()) return out;
  json frames_json = json::array();
  for (const FrameRecord& one : frames) frames_json.push_back(frame_json(one));
  out["frames"] = frames_json;
  out["prepare_seconds"] = prepare.prepare_seconds;
  out["prepare"] = {{"source", prepare.source},
                    {"build_key", prepare.build_key},
                    {"prepare_seconds", prepare.prepare_seconds},
                    {"load_seconds", prepare.load_seconds},
                    {"save_seconds", prepare.save_seconds}};
  if (!prepare.warning.empty()) out["prepare"]["warning"] = prepare.warning;
  out["timings"] = {{"update_ms_min", timings.update_ms_min},       {"update_ms_median", timings.update_ms_median},
                    {"render_ms_min", timings.render_ms_min},       {"render_ms_median", timings.render_ms_median},
                    {"frame_ms_min", timings.frame_ms_min},         {"frame_ms_median", timings.frame_ms_median}};
  if (timings.gpu_render_ms_min) out["timings"]["gpu_render_ms_min"] = *timings.gpu_render_ms_min;
  if (timings.gpu_render_ms_median) out["timings"]["gpu_render_ms_median"] = *timings.gpu_render_ms_median;
  out["metrics"] = metrics;
  if (!metrics_undefined.empty()) out["metrics_undefined"] = metrics_undefined;
  if (empty_reference_frames)
    out["empty_reference"] = {{"frames", *empty_reference_frames}, {"reason", empty_reference_reason}};
  out["memory_bytes"] = memory_bytes;
  out["peak_rss_bytes"] = peak_rss_bytes;
  out["counters"] = counters;
  out["method_record"] = method_record;
  if (lost_flux) {
    json frames_json = json::array();
    for (double value : lost_flux->frames) frames_json.push_back(std::isfinite(value) ? json(value) : json());
    out["lost_flux"] = lost_flux_json(lost_flux->worst);
    out["lost_flux"]["frames"] = frames_json;
    if (!lost_flux->moved_frames.empty()) {
      json moved_json = json::array();
      for (double value : lost_flux->moved_frames) moved_json.push_back(std::isfinite(value) ? json(value) : json());
      out["lost_flux"]["moved_frames"] = moved_json;
    }
  }
  if (!images.is_null()) out["images"] = images;
  if (!reference_images.is_null()) out["reference_images"] = reference_images;
  if (reference_converged) out["reference_converged"] = *reference_converged;
  if (!reference_unconverged.empty()) out["reference_unconverged"] = reference_unconverged;
  if (seeds) out["seeds"] = seeds_json(*seeds);
  return out;
}

std::optional<double> RunRecord::metric(const std::string& name) const {
  if (metrics_undefined.count(name)) return std::nullopt;
  auto found = metrics.find(name);
  if (found == metrics.end() || std::isnan(found->second)) return std::nullopt;
  return found->second;
}

std::optional<MetricInterval> RunRecord::interval(const std::string& name) const {
  const std::optional<double> value = metric(name);
  if (!value) return std::nullopt;
  if (seeds) {
    auto found = seeds->intervals.find(name);
    if (found == seeds->intervals.end()) return std::nullopt;
    return found->second;
  }
  if (stochastic()) return std::nullopt;
  return MetricInterval{*value, 0.0, 0.0, 1};
}

std::optional<double> RunRecord::quantity(const std::string& name) const {
  std::optional<QuantityInfo> info = find_quantity(name);
  if (!info || !ok()) return std::nullopt;
  std::optional<double> value;
  switch (info->source) {
    case QuantitySource::metrics: value = metric(name); break;
    case QuantitySource::timings: value = timings.field(info->field); break;
    case QuantitySource::prepare: value = prepare.prepare_seconds; break;
    case QuantitySource::record:
      if (info->field == "memory_bytes") value = static_cast<double>(memory_bytes);
      else if (info->field == "peak_rss_bytes") value = static_cast<double>(peak_rss_bytes);
      else if (info->field == "receiver_pixels" && receiver_pixels) value = static_cast<double>(*receiver_pixels);
      else if (info->field == "lost_flux" && lost_flux) value = lost_flux->worst.fraction;
      break;
    case QuantitySource::counters: {
      auto found = counters.find(name);
      if (found != counters.end()) value = found->second;
      break;
    }
  }
  if (value && !std::isfinite(*value)) return std::nullopt;
  return value;
}

json RunRecord::knobs() const {
  json merged = json::object();
  for (const json* phase : {&build, &frame, &render})
    if (phase->is_object()) merged.update(*phase);
  if (!variant.empty()) merged["variant"] = variant;
  if (receiver_pixels) merged["receiver_pixels"] = *receiver_pixels;
  return merged;
}

}  // namespace causticbench
