#include "methods/external/external.h"

#include <stdlib.h>

#include <filesystem>

#include <fmt/format.h>

#include "core/assets.h"
#include "core/errors.h"
#include "core/files.h"
#include "core/shell.h"
#include "methods/external/command_template.h"
#include "methods/external/program_output.h"
#include "methods/external/program_process.h"

namespace causticbench {

namespace fs = std::filesystem;

ExternalMethod::ExternalMethod() = default;

ExternalMethod::~ExternalMethod() {
  std::error_code ignored;
  if (!folder_.empty() && !keep_folder_) fs::remove_all(folder_, ignored);
}

void ExternalMethod::prepare(const PrepareContext& context, const ParamSet& build) {
  build_ = build;
  // A folder of its own per prepared instance: runs side by side (shards, tests) never share files.
  std::string pattern = (fs::temp_directory_path() / "causticbench-external-XXXXXX").string();
  if (!mkdtemp(pattern.data()))
    throw std::runtime_error(fmt::format("cannot make a folder for the program's files from {}: {}", pattern, os_error_text(errno)));
  folder_ = pattern;
  exporter_ = std::make_unique<SceneExporter>(folder_);
}

void ExternalMethod::begin_sequence() {
  reports_.clear();
}

void ExternalMethod::update(const FrameContext& frame, const ParamSet& frame_knobs) {
  frame_ = static_cast<int>(frame.frame.frame);
  exporter_->write(frame.frame);
  // Under pixel_samples the frame's program runs once per sub-pixel G-buffer: its figures add up.
  reports_[frame_] = {{"frame", frame_}, {"runs", 0}, {"seconds", 0.0}, {"peak_bytes", 0.0}};
}

namespace {

// Adds what one run of the program took and reported to its frame's report.
void add_run(nlohmann::json& report, double seconds, double peak_bytes, const std::optional<nlohmann::json>& statistics) {
  report["runs"] = report["runs"].get<int>() + 1;
  report["seconds"] = report["seconds"].get<double>() + seconds;
  report["peak_bytes"] = std::max(report["peak_bytes"].get<double>(), peak_bytes);
  if (!statistics) return;
  if (statistics->contains("time_ms"))
    report["time_ms"] = report.value("time_ms", 0.0) + statistics->at("time_ms").get<double>();
  for (const char* group : {"timings_ms", "counters"}) {
    if (!statistics->contains(group)) continue;
    nlohmann::json& sums = report[group];
    if (!sums.is_object()) sums = nlohmann::json::object();
    for (const auto& [name, value] : statistics->at(group).items()) sums[name] = sums.value(name, 0.0) + value.get<double>();
  }
}

}  // namespace

std::string ExternalMethod::fail(const std::string& reason, const std::string& stderr_path) {
  keep_folder_ = true;
  const std::string tail = file_tail(stderr_path);
  return fmt::format("frame {}: the program {}; {}its files are kept in {} (rerun it with `sh {}/command.sh`)", frame_, reason,
                     tail.empty() ? "it wrote nothing to stderr; " : "its stderr ends:\n" + tail, folder_, folder_);
}

Image ExternalMethod::render(const GBuffer& gbuffer, const ParamSet& render) {
  const std::string gbuffer_path = folder_ + "/gbuffer.exr", out = folder_ + "/ec.exr", statistics_path = folder_ + "/stats.json",
                    stderr_path = folder_ + "/stderr.txt";
  write_exr(gbuffer.to_image(), gbuffer_path, GBuffer::channel_names());
  // What a previous frame's program wrote must not pass for this one's.
  fs::remove(out);
  fs::remove(statistics_path);
  std::map<std::string, std::string> values = program_knobs(build_);
  values.insert({{"scene", exporter_->scene_path()},
                                               {"world", exporter_->world_path()},
                                               {"gbuffer", gbuffer_path},
                                               {"out", out},
                                               {"stats", statistics_path},
                                               {"folder", folder_},
                                               {"frame", std::to_string(frame_)},
                                               {"width", std::to_string(gbuffer.width)},
                                               {"height", std::to_string(gbuffer.height)},
                                               {"causticbench", executable_path()}});
  const std::string command = expand_command(build_.text("command"), values);
  // To rerun the frame by hand: from the folder the sweep ran in, where relative paths of the command lead.
  write_text_atomically(folder_ + "/command.sh", "cd " + shell_quoted(fs::current_path().string()) + "\n" + command + "\n");
  const double timeout = build_.real("timeout_seconds");
  const ProgramExit exit = run_program(command, folder_ + "/stdout.txt", stderr_path, timeout);
  if (!exit.succeeded()) throw ProgramError(fail(exit.describe(timeout), stderr_path));
  Image image;
  std::optional<nlohmann::json> statistics;
  try {
    image = read_program_image(out, gbuffer.width, gbuffer.height);
    statistics = read_program_statistics(statistics_path);
  } catch (const std::runtime_error& error) {
    throw ProgramError(fail("exited with status 0, but " + std::string(error.what()), stderr_path));
  }
  add_run(reports_[frame_], exit.seconds, exit.peak_bytes, statistics);
  peak_bytes_ = std::max(peak_bytes_, exit.peak_bytes);
  return image;
}

size_t ExternalMethod::memory_bytes() const { return static_cast<size_t>(peak_bytes_); }

Counters ExternalMethod::counters() const {
  // The program's own time, where it reported one for every frame: beside render_ms, which also pays for
  // starting the process and reading and writing the files.
  double sum = 0.0;
  size_t frames = 0;
  for (const auto& [frame, report] : reports_) {
    if (report["runs"].get<int>() == 0) continue;  // updated, not yet rendered
    if (!report.contains("time_ms")) return {};
    sum += report["time_ms"].get<double>();
    ++frames;
  }
  if (frames == 0) return {};
  return {{"reported_ms", sum / static_cast<double>(frames)}};
}

nlohmann::json ExternalMethod::record() const {
  nlohmann::json frames = nlohmann::json::array();
  for (const auto& [frame, report] : reports_)
    if (report["runs"].get<int>() > 0) frames.push_back(report);
  return {{"program", frames}};
}

}  // namespace causticbench
