// Recomputing stored metrics (declared in recompute_metrics.h).
#include "experiments/recompute_metrics.h"

#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/gbuffer.h"
#include "core/progress.h"
#include "store/result_paths.h"
#include "store/run_folders.h"
#include "experiments/run_measurement.h"
#include "experiments/seed_replicas.h"
#include "store/store_files.h"
#include "store/store_lock.h"
#include "metrics/metrics.h"

namespace causticbench {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The file's image, after its bytes are checked against `checksum` (when the record has one).
Image checked_image(const fs::path& path, const json& checksum) {
  std::optional<std::string> bytes = read_file_bytes(path.string());
  if (!bytes) throw InputError(fmt::format("{} is missing or unreadable", path.string()));
  if (checksum.is_object()) {
    std::string problem = checksum_problem(checksum, *bytes);
    if (!problem.empty()) throw InputError(fmt::format("{} is not the image the record names: {}", path.string(), problem));
  }
  return decode_exr(*bytes, path.string());
}

const json& checksum_of(const json& images, const std::string& file) {
  static const json none;
  return images.is_object() && images.contains(file) ? images[file] : none;
}

// Scores one seed's frames (or a run measured once) again; throws InputError naming what does not match.
void rescore_frames(RunRecord& record, const fs::path& run_folder, const fs::path& reference_folder,
                    const std::vector<std::string>& metrics) {
  std::vector<Image> tests, references;
  std::vector<std::vector<uint8_t>> masks;
  tests.reserve(record.frames.size());
  references.reserve(record.frames.size());
  masks.reserve(record.frames.size());
  for (const FrameRecord& frame : record.frames) {
    tests.push_back(checked_image(run_folder / frame.image, checksum_of(record.images, frame.image)));
    const std::string reference_file = ResultPaths::frame_file(frame.frame) + ".exr";
    references.push_back(
        checked_image(reference_folder / reference_file, checksum_of(record.reference_images, reference_file)));
    // The receiver mask from the stored G-buffer (GBuffer::to_image), which the reference's record checks.
    Image gbuffer = GBuffer::read_image((reference_folder / (ResultPaths::frame_file(frame.frame, "gbuffer") + ".exr")).string());
    if (gbuffer.channels() <= GBuffer::kReceiverChannel || gbuffer.width() != tests.back().width() ||
        gbuffer.height() != tests.back().height())
      throw InputError(fmt::format("the G-buffer of frame {} in {} does not fit the run's image", frame.frame,
                                   reference_folder.string()));
    std::vector<uint8_t> mask(gbuffer.pixel_count());
    for (size_t i = 0; i < mask.size(); ++i) mask[i] = gbuffer.at(i, GBuffer::kReceiverChannel) > 0.5f;
    masks.push_back(std::move(mask));
  }
  std::vector<ScoredFrame> scored;
  for (size_t f = 0; f < record.frames.size(); ++f) {
    ScoredFrame one{record.frames[f].frame, &tests[f], &references[f], &masks[f], std::nullopt};
    if (record.empty_reference_frames) {
      for (int empty : *record.empty_reference_frames)
        if (empty == one.frame) one.empty_reference = "empty reference: " + record.empty_reference_reason;
    }
    scored.push_back(one);
  }
  score_run(record, metrics, scored);
}

// Scores one stored record again: each of its seeds, then their means and intervals.
void rescore(RunRecord& record, const fs::path& run_folder, const fs::path& reference_folder,
             const std::vector<std::string>& metrics) {
  if (!record.seeds) {
    rescore_frames(record, run_folder, reference_folder, metrics);
    return;
  }
  for (SeedRun& seed : record.seeds->runs) {
    RunRecord one = record;  // its images, checksums and empty frames; its frames those of the seed
    one.seeds.reset();
    one.frames = seed.frames;
    rescore_frames(one, run_folder, reference_folder, metrics);
    seed.frames = one.frames;
    seed.metrics = one.metrics;
    seed.metrics_undefined = one.metrics_undefined;
  }
  aggregate_seeds(record);
}

}  // namespace

RecomputeSummary recompute_metrics(const std::string& experiment_folder) {
  const fs::path folder = fs::absolute(experiment_folder).lexically_normal();
  const fs::path experiment_file = folder / "experiment.json";
  if (!fs::is_regular_file(experiment_file))
    throw InputError(fmt::format("'{}' is not an experiment results folder: it has no experiment.json", experiment_folder));
  const json experiment = json::parse(read_text(experiment_file.string()), nullptr, false);
  if (!experiment.is_object() || !experiment.contains("runs") || !experiment["runs"].is_array())
    throw InputError(fmt::format("{}: expected a JSON object with \"runs\"", experiment_file.string()));
  std::vector<std::string> metrics;
  for (const json& name : experiment.value("metrics", json::array()))
    if (name.is_string()) metrics.push_back(name.get<std::string>());
  for (const std::string& name : metrics) find_metric(name);  // an unknown metric fails before any work
  const std::string name = experiment.value("name", folder.filename().string());
  const std::string fallback_reference = experiment.value("reference_key", "");
  const ResultPaths paths{folder.parent_path().string()};

  RecomputeSummary summary;
  const json& runs = experiment["runs"];
  Progress progress("recomputing metrics", static_cast<double>(runs.size()));
  size_t done = 0;
  for (const json& key_json : runs) {
    const std::string key = key_json.is_string() ? key_json.get<std::string>() : "";
    progress.update(static_cast<double>(done++), key);
    const fs::path run_folder = paths.run(name, key);
    // Under the run's lock: a `run` of the same experiment cannot replace the folder meanwhile.
    StoreLock lock = StoreLock::acquire(paths.run_lock(name, key), "run " + key);
    StoredRun stored = inspect_stored_run(run_folder.string());
    if (stored.state != StoredRun::State::stored) {
      ++summary.skipped;
      if (stored.state == StoredRun::State::damaged) summary.problems.push_back(stored.problem);
      continue;
    }
    RunRecord record = RunRecord::from_json(stored.record);
    if (!record.ok()) {
      ++summary.skipped;
      continue;
    }
    const std::string reference_key = record.reference_key.empty() ? fallback_reference : record.reference_key;
    try {
      rescore(record, run_folder, paths.reference(reference_key), metrics);
    } catch (const InputError& problem) {
      ++summary.skipped;
      summary.problems.push_back(fmt::format("run {} ({}): {}; its record is left as it was", key, record.label,
                                             problem.what()));
      continue;
    }
    write_text_atomically((run_folder / "record.json").string(), record.to_json().dump(2) + "\n");
    ++summary.recomputed;
  }
  progress.finish(fmt::format("{} recomputed, {} skipped", summary.recomputed, summary.skipped));
  return summary;
}

}  // namespace causticbench
