// The reference cache, results/references/<key>/: loading a stored frame after its checks, computing a
// missing or damaged one under the reference's lock, and the folder's record.json summary
// (store/reference_cache.h; docs/results-format.md).
#include <filesystem>
#include <regex>

#include <fmt/format.h>

#include "core/files.h"
#include "store/record_check.h"
#include "store/reference_cache.h"
#include "store/store_files.h"
#include "store/store_lock.h"
#include "methods/reference/reference.h"
#include "methods/registry.h"

namespace causticbench {

namespace fs = std::filesystem;

namespace {

struct FrameFiles {
  fs::path image, gbuffer, error, record;
};

FrameFiles frame_files(const fs::path& folder, int frame) {
  return {folder / (ResultPaths::frame_file(frame) + ".exr"), folder / (ResultPaths::frame_file(frame, "gbuffer") + ".exr"),
          folder / (ResultPaths::frame_file(frame, "error") + ".exr"),
          folder / (ResultPaths::frame_file(frame, "record") + ".json")};
}

// A stored frame as found: usable (its image decoded), absent, or damaged (`problem` says why).
struct StoredFrame {
  bool present = false;
  std::string problem;
  Image image;
  nlohmann::json record, checksum;
  bool usable() const { return present && problem.empty(); }
};

std::optional<nlohmann::json> read_frame_record(const fs::path& path, int frame, std::string& problem) {
  std::optional<std::string> text = read_file_bytes(path.string());
  if (!text) {
    problem = fmt::format("{}: missing or unreadable", path.string());
    return std::nullopt;
  }
  nlohmann::json record = nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false);
  problem = record.is_discarded() ? "not valid JSON (truncated?)" : reference_frame_record_problem(record, frame);
  if (!problem.empty()) {
    problem = fmt::format("{}: {}", path.string(), problem);
    return std::nullopt;
  }
  return record;
}

// Whether a frame record names other scene content than `content_hash` (records written before the field
// name none and pass).
bool computed_for_other_content(const nlohmann::json& record, const std::string& content_hash) {
  return record.contains("scene_content") && record["scene_content"] != content_hash;
}

// A frame is stored once its record is: the record is written last and names its images' checksums.
// `content_hash` is the request's: the key hashes the scene file's text only,
// so a mesh or environment map edited in place is caught here (frames stored before the field pass).
StoredFrame find_stored_frame(const fs::path& folder, int frame, const GBuffer& gbuffer, const std::string& content_hash) {
  StoredFrame stored;
  const FrameFiles files = frame_files(folder, frame);
  if (!fs::exists(files.record)) return stored;
  stored.present = true;
  std::optional<nlohmann::json> record = read_frame_record(files.record, frame, stored.problem);
  if (!record) return stored;
  if (computed_for_other_content(*record, content_hash)) {
    stored.problem = fmt::format("{}: computed for other scene content (scene_content {}, now {}: a mesh or environment "
                                 "map the scene names has changed since)",
                                 files.record.string(), (*record)["scene_content"].dump(), content_hash);
    return stored;
  }
  std::optional<std::string> bytes = read_file_bytes(files.image.string());
  if (!bytes) {
    stored.problem = fmt::format("{}: missing or unreadable", files.image.string());
    return stored;
  }
  // References written before checksums have none: for them, decoding is the check.
  if (record->contains("image")) {
    std::string problem = checksum_problem((*record)["image"], *bytes);
    if (!problem.empty()) {
      stored.problem = fmt::format("{}: {}", files.image.string(), problem);
      return stored;
    }
  }
  if (record->contains("gbuffer")) {
    std::optional<std::string> gbuffer_bytes = read_file_bytes(files.gbuffer.string());
    std::string problem = gbuffer_bytes ? checksum_problem((*record)["gbuffer"], *gbuffer_bytes) : "missing or unreadable";
    if (!problem.empty()) {
      stored.problem = fmt::format("{}: {}", files.gbuffer.string(), problem);
      return stored;
    }
  }
  try {
    stored.image = decode_exr(*bytes, files.image.string());
  } catch (const std::runtime_error& error) {
    stored.problem = error.what();
    return stored;
  }
  if (stored.image.width() != gbuffer.width || stored.image.height() != gbuffer.height || stored.image.channels() < 3) {
    stored.problem = fmt::format("{}: {} x {} pixels with {} channels, expected {} x {} RGB", files.image.string(),
                                 stored.image.width(), stored.image.height(), stored.image.channels(), gbuffer.width,
                                 gbuffer.height);
    return stored;
  }
  stored.record = std::move(*record);
  stored.checksum = content_checksum(*bytes);
  return stored;
}

void use_frame(VariantFrames& frames, int frame, Image image, const nlohmann::json& record, nlohmann::json checksum) {
  frames.reference[frame] = std::move(image);
  frames.reference_checksums[frame] = std::move(checksum);
  if (std::optional<std::string> reason = reference_unconverged_reason(record)) frames.unconverged[frame] = *reason;
}

// Why a reference that stopped on its time cap cannot stand for its key: on a faster machine it would
// have run more passes.
std::optional<std::string> time_cap_reason(const nlohmann::json& record, const ParamSet& params) {
  if (record.value("stop_reason", "") != "max_seconds") return std::nullopt;
  return fmt::format("stopped by its time cap (max_seconds = {:g} s) after {} passes with reference error {:.3g} "
                     "(target_error {:g}): its pass count depends on the speed of the machine that computed it",
                     params.real("max_seconds"), record.value("passes", 0), record.value("error_estimate", 0.0),
                     params.real("target_error"));
}

// Computes one frame's reference through the lifecycle driver and stores it: the EXRs first, the record,
// which names their checksums, last.
void compute_frame(const ReferenceRequest& request, const fs::path& folder, int frame, VariantFrames& frames,
                   std::unique_ptr<RestPose>& rest) {
  const PosedFrame& posed = *frames.posed.at(frame);
  fmt::print(stderr, "reference {} frame {}{}: computing (cached in {})\n", request.reference_key, frame, request.label,
             folder.string());
  std::unique_ptr<CausticMethod> method = create_method("reference");
  const PhaseKnobs knobs = split_phases(request.params, method->info().params);
  auto zero = frames.posed.find(0);
  const PosedFrame* frame_zero = zero == frames.posed.end() ? nullptr : zero->second.get();
  prepare_method(*method, prepare_context(request.scene, request.frames, frame_zero, rest), knobs.build);
  Image caustic =
      std::move(play_sequence(*method, {&posed}, knobs.frame, {knobs.render}, TimingProtocol{false, 1}).front().images.front());
  const FrameFiles files = frame_files(folder, frame);
  const std::string image_bytes = encode_exr(caustic), gbuffer_bytes = encode_exr(posed.gbuffer.to_image(), GBuffer::channel_names());
  // The estimated RMS error of every pixel (W/m^2), beside the image it qualifies.
  const auto* reference = dynamic_cast<const ReferenceMethod*>(method.get());
  if (!reference) throw std::logic_error("the method named reference is not ReferenceMethod");
  const std::string error_bytes = encode_exr(reference->error_map());
  write_file_atomically(files.image.string(), image_bytes);
  write_file_atomically(files.gbuffer.string(), gbuffer_bytes);
  write_file_atomically(files.error.string(), error_bytes);
  nlohmann::json record = method->record();
  record["frame"] = frame;
  record["params"] = request.params.to_json();
  record["scene_content"] = request.content_hash;
  record["image"] = content_checksum(image_bytes);
  record["image"]["file"] = files.image.filename().string();
  record["gbuffer"] = content_checksum(gbuffer_bytes);
  record["gbuffer"]["file"] = files.gbuffer.filename().string();
  record["error_map"] = content_checksum(error_bytes);
  record["error_map"]["file"] = files.error.filename().string();
  std::optional<std::string> reason = time_cap_reason(record, request.params);
  record["converged"] = !reason;
  if (reason) {
    record["unconverged_reason"] = *reason;
    fmt::print(stderr, "warning: reference {} frame {} is not converged: {}; runs measured against it say so\n",
               request.reference_key, frame, *reason);
  }
  write_text_atomically(files.record.string(), record.dump(2) + "\n");
  use_frame(frames, frame, std::move(caustic), record, content_checksum(image_bytes));
}

// record.json summarises every stored frame (of this and earlier experiments); its top level is the
// first frame's record. Written under the reference's lock, so that no frame of another process is lost.
void write_summary(const fs::path& folder, const std::string& key) {
  static const std::regex frame_record("record_([0-9]+)\\.json");
  nlohmann::json summary = nlohmann::json::object(), stored_frames = nlohmann::json::object();
  bool converged = true;
  int first = -1;
  for (const auto& entry : fs::directory_iterator(folder)) {
    std::string file = entry.path().filename().string();
    std::smatch match;
    if (!std::regex_match(file, match, frame_record)) continue;  // not the temporary files beside them
    int index = std::stoi(match[1].str());
    std::string problem;
    std::optional<nlohmann::json> stored = read_frame_record(entry.path(), index, problem);
    if (!stored) continue;  // damaged: recomputed by the next run that needs it
    std::optional<std::string> reason = reference_unconverged_reason(*stored);
    converged = converged && !reason;
    stored_frames[std::to_string(index)] = {{"error_estimate", (*stored)["error_estimate"]}, {"passes", (*stored)["passes"]},
                                            {"seconds", (*stored)["seconds"]}, {"stop_reason", (*stored)["stop_reason"]},
                                            {"converged", !reason}};
    // What the frame requires (issue 52); absent from references computed before it was measured.
    if (stored->contains("path_classes")) stored_frames[std::to_string(index)]["path_classes"] = (*stored)["path_classes"];
    if (first < 0 || index < first) {
      first = index;
      summary = *stored;
    }
  }
  summary["frames"] = stored_frames;
  summary["key"] = key;
  summary["converged"] = converged;
  write_text_atomically((folder / "record.json").string(), summary.dump(2) + "\n");
}

// The summary is what the report reads (the reference error, the convergence history): a damaged one is
// written again from the frames' records.
bool summary_is_readable(const fs::path& folder) {
  std::optional<std::string> text = read_file_bytes((folder / "record.json").string());
  if (!text) return false;
  nlohmann::json summary = nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false);
  return summary.is_object() && summary.contains("key") && summary.contains("frames");
}

}  // namespace

VariantFrames reference_frames(const ReferenceRequest& request, const ResultPaths& paths) {
  VariantFrames frames;
  const fs::path folder = paths.reference(request.reference_key);
  remove_stale_partial_files(folder.string());  // of dead processes only: a live one may be writing here
  std::vector<int> missing;
  for (int frame : request.frames) {
    const PosedFrame& posed = *(frames.posed[frame] = std::make_unique<PosedFrame>(request.scene, frame));
    StoredFrame stored = find_stored_frame(folder, frame, posed.gbuffer, request.content_hash);
    if (stored.usable()) use_frame(frames, frame, std::move(stored.image), stored.record, std::move(stored.checksum));
    else missing.push_back(frame);
  }
  if (missing.empty() && summary_is_readable(folder)) return frames;

  make_folders(folder.string());
  const std::string what = fmt::format("reference {}{}", request.reference_key, request.label);
  StoreLock lock = StoreLock::acquire(paths.reference_lock(request.reference_key), what);
  remove_stale_partial_files(folder.string(), /*folder_is_locked=*/true);
  std::unique_ptr<RestPose> rest;  // posed only if a frame must be computed
  bool computed = false;
  for (int frame : missing) {
    // Looked at again under the lock: the process we waited for may have stored it.
    StoredFrame stored = find_stored_frame(folder, frame, frames.posed.at(frame)->gbuffer, request.content_hash);
    if (stored.usable()) {
      use_frame(frames, frame, std::move(stored.image), stored.record, std::move(stored.checksum));
      continue;
    }
    if (stored.present) {
      fmt::print(stderr, "warning: {} frame {}: {}; computing it again\n", what, frame, stored.problem);
    }
    compute_frame(request, folder, frame, frames, rest);
    computed = true;
  }
  if (computed || !summary_is_readable(folder)) {
    if (!computed) fmt::print(stderr, "warning: {}: unreadable; writing it again from the frames' records\n",
                              (folder / "record.json").string());
    write_summary(folder, request.reference_key);
  }
  return frames;
}

std::optional<nlohmann::json> stored_reference_checksums(const ResultPaths& paths, const std::string& reference_key,
                                                         const std::vector<int>& frames) {
  nlohmann::json checksums = nlohmann::json::object();
  for (int frame : frames) {
    const FrameFiles files = frame_files(paths.reference(reference_key), frame);
    std::string problem;
    std::optional<nlohmann::json> record = read_frame_record(files.record, frame, problem);
    if (!record || !record->contains("image") || !(*record)["image"].is_object()) return std::nullopt;
    nlohmann::json checksum = (*record)["image"];
    checksum.erase("file");
    checksums[files.image.filename().string()] = checksum;
  }
  return checksums;
}

bool stored_reference_content_differs(const ResultPaths& paths, const std::string& reference_key,
                                      const std::string& content_hash, const std::vector<int>& frames) {
  for (int frame : frames) {
    std::string problem;
    std::optional<nlohmann::json> record =
        read_frame_record(frame_files(paths.reference(reference_key), frame).record, frame, problem);
    if (record && computed_for_other_content(*record, content_hash)) return true;
  }
  return false;
}

nlohmann::json reference_fields(const VariantFrames& frames, const std::vector<int>& experiment_frames) {
  nlohmann::json images = nlohmann::json::object();
  std::optional<std::string> unconverged;
  for (int frame : experiment_frames) {
    images[ResultPaths::frame_file(frame) + ".exr"] = frames.reference_checksums.at(frame);
    auto reason = frames.unconverged.find(frame);
    if (reason != frames.unconverged.end() && !unconverged)
      unconverged = experiment_frames.size() > 1 ? fmt::format("frame {}: {}", frame, reason->second) : reason->second;
  }
  nlohmann::json fields = {{"reference_images", images}, {"reference_converged", !unconverged}};
  if (unconverged) fields["reference_unconverged"] = *unconverged;
  return fields;
}

}  // namespace causticbench
