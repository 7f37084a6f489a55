#include "experiments/reference_frames.h"

#include <filesystem>
#include <fstream>
#include <set>

#include <fmt/format.h>

#include "core/direct_lighting.h"
#include "core/errors.h"
#include "core/files.h"
#include "methods/registry.h"

namespace causticbench {

namespace fs = std::filesystem;

VariantFrames variant_frames(const Experiment& experiment, const SceneVariant& variant, const ResultPaths& paths) {
  VariantFrames frames;
  fs::path folder = paths.reference(variant.reference_key);
  fs::create_directories(folder);
  bool computed = false;
  std::unique_ptr<RestPose> rest;  // posed only if a frame must be computed
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
    const PhaseKnobs knobs = split_phases(experiment.reference_params, method->info().params);
    auto zero = frames.posed.find(0);
    const PosedFrame* frame_zero = zero == frames.posed.end() ? nullptr : zero->second.get();
    prepare_method(*method, prepare_context(variant.scene, experiment.frames, frame_zero, rest), knobs.build);
    Image caustic =
        std::move(play_sequence(*method, {&posed}, knobs.frame, {knobs.render}, TimingProtocol{false, 1}).front().images.front());
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

namespace {

// Light samples per pixel and light of the direct irradiance that the empty-reference rule compares E_c
// with: the rule's threshold is a millionth of it, so a rough estimate decides as a converged one would.
constexpr int kPresenceDirectSamples = 4;
constexpr uint64_t kPresenceDirectSeed = 1;


// How much caustic light each frame of the variant's reference has in view (metrics/caustic_presence.h).
std::vector<FramePresence> reference_presence(const Experiment& experiment, const VariantFrames& frames) {
  std::vector<FramePresence> result;
  for (int frame : experiment.frames) {
    const PosedFrame& posed = *frames.posed.at(frame);
    Image direct = direct_irradiance(posed.tracer, posed.gbuffer, kPresenceDirectSamples, kPresenceDirectSeed);
    result.push_back({frame, measure_caustic_presence(frames.reference.at(frame), direct, posed.gbuffer.receiver)});
  }
  return result;
}

std::vector<FramePresence> empty_frames(const std::vector<FramePresence>& presences) {
  std::vector<FramePresence> empty;
  for (const FramePresence& entry : presences)
    if (entry.presence.empty()) empty.push_back(entry);
  return empty;
}

// "frame 0" or "frame 0 (and frames 3, 4)".
std::string frames_text(const std::vector<FramePresence>& frames) {
  std::string text = fmt::format("frame {}", frames.front().frame);
  if (frames.size() == 1) return text;
  std::vector<std::string> others;
  for (size_t i = 1; i < frames.size(); ++i) others.push_back(std::to_string(frames[i].frame));
  return text + fmt::format(" (and frame{} {})", others.size() == 1 ? "" : "s", join(others, ", "));
}

// An empty reference is an input error: the scene, its camera or its lights are not what the experiment
// needs, and every score against it would be undefined or a meaningless perfect value.
[[noreturn]] void throw_empty_reference(const Experiment& experiment, const SceneVariant& variant,
                                        const ResultPaths& paths, const std::vector<FramePresence>& empty) {
  throw InputError(fmt::format(
      "{}: the reference of scene {} (variant {}) has no caustic in view on {}: {}. Every method would be scored "
      "against nothing; {}. No run was started (the reference is kept in {}). An experiment that means to measure "
      "an empty caustic (an extremes case) sets `empty_reference_expected: true`; its runs are then reported as "
      "\"empty reference\", not scored.",
      experiment.source, experiment.scene_path, variant.name, frames_text(empty), empty.front().presence.describe(),
      kEmptyCausticHint, paths.reference(variant.reference_key)));
}


}  // namespace

ReferenceCheck check_references(const Experiment& experiment, const std::vector<const RunSpec*>& pending,
                                const ResultPaths& paths) {
  std::set<size_t> variants;
  for (const RunSpec* run : pending) variants.insert(run->variant);
  ReferenceCheck check;
  for (size_t index : variants) {
    const SceneVariant& variant = experiment.variants.at(index);
    check.kept_frames = VariantFrames{};  // one variant's frames in memory at a time
    check.kept_frames = variant_frames(experiment, variant, paths);
    check.kept_variant = index;
    std::vector<FramePresence> empty = empty_frames(reference_presence(experiment, check.kept_frames));
    if (empty.empty()) continue;
    if (!experiment.empty_reference_expected) throw_empty_reference(experiment, variant, paths, empty);
    fmt::print(stderr, "reference {} (variant {}) has no caustic in view on {}: its runs are stored as \"empty "
               "reference\", not scored (empty_reference_expected)\n",
               variant.reference_key, variant.name, frames_text(empty));
    check.empty[index] = std::move(empty);
  }
  if (variants.size() > 1) {
    // The runs start with the first variant: keeping the last one's frames would hold two variants at once.
    check.kept_frames = VariantFrames{};
    check.kept_variant.reset();
  }
  if (experiment.empty_reference_expected && check.empty.empty() && !variants.empty()) {
    fmt::print(stderr, "note: empty_reference_expected is set, but every reference checked has a caustic in view; "
               "the runs are scored as usual\n");
  }
  return check;
}


}  // namespace causticbench
