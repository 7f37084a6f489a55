#include "store/record_check.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <initializer_list>
#include <vector>

#include <fmt/format.h>

#include "metrics/metrics.h"
#include "store/run_record.h"
#include "store/store_files.h"

namespace causticbench {

namespace fs = std::filesystem;

namespace {

enum class Kind { string, integer, number, object, array };

struct Field {
  const char* name;
  Kind kind;
};

const char* kind_name(Kind kind) {
  switch (kind) {
    case Kind::string: return "a string";
    case Kind::integer: return "an integer";
    case Kind::number: return "a number";
    case Kind::object: return "an object";
    case Kind::array: return "an array";
  }
  return "?";
}

bool has_kind(const nlohmann::json& value, Kind kind) {
  switch (kind) {
    case Kind::string: return value.is_string();
    case Kind::integer: return value.is_number_integer();
    case Kind::number: return value.is_number();
    case Kind::object: return value.is_object();
    case Kind::array: return value.is_array();
  }
  return false;
}

// The first required field that is missing or of another type, as "field 'x' is missing".
std::string schema_problem(const nlohmann::json& object, std::initializer_list<Field> fields, const std::string& where = "") {
  for (const Field& field : fields) {
    std::string name = where + "'" + field.name + "'";
    if (!object.contains(field.name)) return fmt::format("field {} is missing", name);
    if (!has_kind(object[field.name], field.kind)) {
      return fmt::format("field {} is {}, expected {}", name, object[field.name].type_name(), kind_name(field.kind));
    }
  }
  return "";
}

std::string image_problem(const nlohmann::json& record, const std::string& run_folder, const std::string& image) {
  if (image.empty() || image.find('/') != std::string::npos || image.front() == '.') {
    return fmt::format("it names the image '{}', not a file of its folder", image);
  }
  std::string path = (fs::path(run_folder) / image).string();
  std::optional<std::string> bytes = read_file_bytes(path);
  if (!bytes) return fmt::format("its image {} is missing or unreadable", image);
  const nlohmann::json* images = record.contains("images") ? &record["images"] : nullptr;
  if (!images) return bytes->empty() ? fmt::format("its image {} is empty", image) : "";
  if (!images->is_object() || !images->contains(image)) return fmt::format("'images' has no checksum of {}", image);
  std::string problem = checksum_problem((*images)[image], *bytes);
  return problem.empty() ? "" : fmt::format("its image {}: {}", image, problem);
}

// A negative time or size cannot have been measured: an ok record holding one was edited or damaged, and
// counting it would put it on a front (issue 30, 13). (A value beyond the largest double, 1.8e308, is no
// JSON number at all: such a record fails to parse and is damaged already.)
// A metric's value as stored: undefined (null, read as NaN), or finite within what the metric can be
// (MetricInfo::minimum and maximum). An infinite value cannot have been computed and stored (JSON has
// none; a number such as 1.8e308, beyond the largest double, reads as infinite), and FLIP 3 cannot be.
std::string metric_values_problem(const std::map<std::string, double>& metrics, const std::string& where) {
  for (const auto& [name, value] : metrics) {
    if (std::isnan(value)) continue;
    const MetricInfo* metric = metric_info(name);
    const double minimum = metric ? metric->minimum : -std::numeric_limits<double>::infinity();
    const double maximum = metric ? metric->maximum : std::numeric_limits<double>::infinity();
    if (!std::isfinite(value) || value < minimum || value > maximum)
      return fmt::format("{}metric {} is {}: expected a finite value in [{}, {}]", where, name, value, minimum, maximum);
  }
  return "";
}

std::string measured_value_problem(const RunRecord& record) {
  for (const FrameRecord& frame : record.frames) {
    for (const auto* series : {&frame.update_ms, &frame.render_ms, &frame.gpu_render_ms})
      for (double value : *series)
        if (!(value >= 0.0 && std::isfinite(value)))
          return fmt::format("frame {} holds a time of {} ms: expected a finite time >= 0", frame.frame, value);
    if (std::string problem = metric_values_problem(frame.metrics, fmt::format("frame {}: ", frame.frame)); !problem.empty())
      return problem;
  }
  if (std::string problem = metric_values_problem(record.metrics, ""); !problem.empty()) return problem;
  if (record.seeds) {
    for (const SeedRun& seed : record.seeds->runs)
      if (std::string problem = metric_values_problem(seed.metrics, fmt::format("seed {}: ", seed.seed)); !problem.empty())
        return problem;
  }
  const PrepareRecord& prepare = record.prepare;
  for (double value : {prepare.prepare_seconds, prepare.load_seconds, prepare.save_seconds})
    if (!(value >= 0.0 && std::isfinite(value))) return fmt::format("a prepare time of {} s: expected a finite time >= 0", value);
  if (record.memory_bytes < 0 || record.peak_rss_bytes < 0)
    return fmt::format("a memory size of {} bytes: expected a size >= 0", std::min(record.memory_bytes, record.peak_rss_bytes));
  if (record.lost_flux && !(record.lost_flux->worst.fraction >= 0.0 && record.lost_flux->worst.fraction <= 1.0))
    return fmt::format("a lost flux fraction of {}: expected a fraction in [0, 1]", record.lost_flux->worst.fraction);
  return "";
}

}  // namespace

std::string run_record_problem(const nlohmann::json& record, const std::string& run_folder) {
  RunRecord parsed;
  try {
    parsed = RunRecord::from_json(record);
  } catch (const RecordError& error) {
    return error.what();
  }
  std::string folder_name = fs::path(run_folder).filename().string();
  if (parsed.key != folder_name) return fmt::format("its key is '{}', but its folder is {}", parsed.key, folder_name);
  if (!parsed.ok()) return "";
  if (std::string problem = measured_value_problem(parsed); !problem.empty()) return problem;
  for (const FrameRecord& frame : parsed.frames) {
    std::string problem = image_problem(record, run_folder, frame.image);
    if (!problem.empty()) return problem;
  }
  if (parsed.seeds) {
    // Every seed's images and the standard-deviation images: each one the store wrote with its checksum.
    std::vector<std::string> images = parsed.seeds->stddev_images;
    for (const SeedRun& seed : parsed.seeds->runs) {
      if (seed.frames.size() != parsed.frames.size())
        return fmt::format("seed {} has {} frames, the run {}", seed.seed, seed.frames.size(), parsed.frames.size());
      for (const FrameRecord& frame : seed.frames) images.push_back(frame.image);
    }
    for (const std::string& image : images) {
      std::string problem = image_problem(record, run_folder, image);
      if (!problem.empty()) return problem;
    }
  }
  return "";
}

std::string reference_frame_record_problem(const nlohmann::json& record, int frame) {
  if (!record.is_object()) return fmt::format("it is {}, not a JSON object", record.type_name());
  std::string problem = schema_problem(record, {{"frame", Kind::integer},
                                                {"passes", Kind::integer},
                                                {"seconds", Kind::number},
                                                {"error_estimate", Kind::number},
                                                {"stop_reason", Kind::string}});
  if (!problem.empty()) return problem;
  if (record["frame"].get<int64_t>() != frame) return fmt::format("it is the record of frame {}", record["frame"].get<int64_t>());
  return "";
}

std::optional<std::string> reference_unconverged_reason(const nlohmann::json& frame_record) {
  if (!frame_record.is_object()) return std::nullopt;
  if (frame_record.contains("converged") && frame_record["converged"] == true) return std::nullopt;
  if (frame_record.contains("unconverged_reason") && frame_record["unconverged_reason"].is_string())
    return frame_record["unconverged_reason"].get<std::string>();
  // Records written before the flag: the stop reason says it.
  if (frame_record.value("stop_reason", "") == "max_seconds")
    return "stopped by its time cap (max_seconds), so its pass count depends on the speed of the machine that computed it";
  return std::nullopt;
}

}  // namespace causticbench
