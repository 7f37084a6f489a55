#include "experiments/runner.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/progress.h"
#include "experiments/light_account.h"
#include "experiments/reference_frames.h"
#include "store/result_paths.h"
#include "store/run_folders.h"
#include "experiments/run_measurement.h"
#include "experiments/prepare_builds.h"
#include "experiments/run_selection.h"
#include "experiments/seed_replicas.h"
#include "experiments/shard_plan.h"
#include "store/store_files.h"
#include "core/staging_folder.h"
#include "store/build_cache.h"
#include "store/result_store.h"
#include "methods/lifecycle.h"
#include "methods/memory_estimate.h"
#include "methods/method_runner.h"
#include "methods/registry.h"

namespace causticbench {

namespace fs = std::filesystem;

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

// At most this many runs are claimed (their locks held, one file descriptor each) and played together;
// runs that differ only in render knobs share each frame's update() within such a batch.
constexpr size_t kRunsPerBatch = 256;
// What a batch of runs measured with several seeds may hold in images before they are stored.
constexpr double kSeedImageBytes = 2.0 * (1 << 30);

void store_run(ResultStore& store, const RunClaim& claim, const RunOutcome& outcome) {
  std::vector<std::pair<std::string, std::string>> images;
  for (const auto& [frame, image] : outcome.images) images.push_back({ResultPaths::frame_file(frame) + ".exr", encode_exr(image)});
  for (const auto& [file, image] : outcome.more_images) images.push_back({file, encode_exr(image)});
  store.put(claim, images, outcome.record.to_json());
}

void store_failure(ResultStore& store, const RunClaim& claim, const Experiment& experiment, const RunSpec& run,
                   const std::string& error) {
  RunOutcome outcome;
  outcome.record = run_identity(experiment, run);
  outcome.record.status = "failed";
  outcome.record.error = error;
  store_run(store, claim, outcome);
}

// Pending runs grouped by (variant, method, build knobs): prepare once per group (or load the build
// from results/builds, which serves every variant, experiment and process); within a group, by frame
// knobs: runs that differ only in render knobs share update(). Groups come one variant after another, so
// that only one variant's frames are posed at a time.
struct Group {
  std::vector<std::vector<PendingRun>> by_frame_knobs;
};

std::vector<Group> group_runs(const std::vector<PendingRun>& pending) {
  std::vector<Group> groups;
  std::vector<std::map<std::string, size_t>> frame_index;
  std::map<std::string, size_t> group_of;
  for (const PendingRun& entry : pending) {
    const RunSpec& run = *entry.run;
    std::string group_key = std::to_string(run.variant) + "/" + run.method + run.build.to_json().dump();
    auto [it, inserted] = group_of.insert({group_key, groups.size()});
    if (inserted) {
      groups.emplace_back();
      frame_index.emplace_back();
    }
    Group& group = groups[it->second];
    auto [sub, new_sub] = frame_index[it->second].insert({run.frame.to_json().dump(), group.by_frame_knobs.size()});
    if (new_sub) group.by_frame_knobs.emplace_back();
    group.by_frame_knobs[sub->second].push_back(entry);
  }
  std::stable_sort(groups.begin(), groups.end(), [](const Group& a, const Group& b) {
    return a.by_frame_knobs.front().front().run->variant < b.by_frame_knobs.front().front().run->variant;
  });
  return groups;
}

struct ClaimedRun {
  const RunSpec* run;
  RunClaim claim;
};

// Plays and stores pending runs, each only under its lock; the runs whose lock another process holds
// are handed back, for the caller to wait for.
class RunExecutor {
 public:
  RunExecutor(const Experiment& experiment, ResultStore& store, ReferenceCheck& references, RunSummary& summary,
              size_t pending)
      : experiment_(experiment), store_(store), paths_(store.paths()), builds_(store.paths().builds()),
        references_(references), summary_(summary),
        progress_(fmt::format("run {}", experiment.name), static_cast<double>(pending)) {}

  std::vector<PendingRun> execute(const std::vector<PendingRun>& pending) {
    std::vector<PendingRun> held_by_others;
    for (const Group& group : group_runs(pending)) execute_group(group, held_by_others);
    return held_by_others;
  }

  // Another process stored the run while this one waited for it.
  void stored_by_another(const RunSpec& run) {
    ++summary_.stored;
    progress_.update(static_cast<double>(++done_), run.label + " (stored by another process)");
  }

  void finish() { progress_.finish(fmt::format("{} runs, {} failed", done_, summary_.failed)); }

 private:
  // The report's flag (experiments/light_account.h), said as the run is stored: light that neither the
  // method's lost flux nor its declared limits account for, against its reference's path-class split.
  void warn_of_unexplained_light(const RunSpec& run, const RunRecord& record) {
    const std::string& key = experiment_.variants.at(run.variant).reference_key;
    auto found = reference_records_.find(key);
    if (found == reference_records_.end()) {
      nlohmann::json stored;
      try {
        stored = nlohmann::json::parse(read_text(paths_.reference(key) + "/record.json", "a reference record"));
      } catch (const std::exception&) {
        stored = nullptr;  // no split to account against: the report says nothing either
      }
      found = reference_records_.emplace(key, std::move(stored)).first;
    }
    const std::optional<LightAccount> account = account_for_record(found->second, record);
    if (account && account->flagged) fmt::print(stderr, "warning: run {} {}\n", run.label, describe_light_account(*account));
  }

  void execute_group(const Group& group, std::vector<PendingRun>& held_by_others) {
    const RunSpec& first = *group.by_frame_knobs.front().front().run;
    const SceneVariant& variant = experiment_.variants.at(first.variant);
    std::unique_ptr<CausticMethod> method;
    PrepareOutcome prepared;
    std::string prepare_error;
    const size_t per_batch = runs_per_batch(first);
    for (const std::vector<PendingRun>& runs : group.by_frame_knobs) {
      for (size_t begin = 0; begin < runs.size(); begin += per_batch) {
        std::vector<PendingRun> batch(runs.begin() + begin, runs.begin() + std::min(runs.size(), begin + per_batch));
        std::vector<ClaimedRun> claimed = claim(batch, held_by_others);
        if (claimed.empty()) continue;
        use_variant(first.variant);
        if (!method) {
          try {
            method = create_method(first.method);
            prepare_error = prepare(*method, variant, first, prepared);
          } catch (const MethodError& error) {  // its constructor failed
            prepare_error = error.what();
          }
        }
        if (!prepare_error.empty()) {
          for (const ClaimedRun& run : claimed) fail(run, prepare_error);
          continue;
        }
        play(*method, prepared, claimed);
      }
    }
  }

  // A batch holds every seed's images of its runs until they are stored: with several seeds, as many
  // runs as keep them within kSeedImageBytes.
  size_t runs_per_batch(const RunSpec& run) const {
    const int seeds = seed_count(experiment_, run);
    if (seeds == 1) return kRunsPerBatch;
    const Camera& camera = experiment_.variants.at(run.variant).scene.camera;
    const double bytes = 12.0 * camera.width * camera.height * static_cast<double>(experiment_.frames.size()) * (seeds + 1);
    return std::clamp<size_t>(static_cast<size_t>(kSeedImageBytes / bytes), 1, kRunsPerBatch);
  }

  // The runs of `batch` whose lock this process takes and that still need running.
  std::vector<ClaimedRun> claim(const std::vector<PendingRun>& batch, std::vector<PendingRun>& held_by_others) {
    std::vector<ClaimedRun> claimed;
    for (const PendingRun& pending : batch) {
      bool held = false;
      std::optional<RunClaim> claim =
          store_.try_claim(run_address(experiment_, *pending.run), pending.seen, pending.replace_stored, held);
      if (held) {
        held_by_others.push_back(pending);
      } else if (!claim) {
        stored_by_another(*pending.run);
      } else {
        claimed.push_back({pending.run, std::move(*claim)});
      }
    }
    return claimed;
  }

  void use_variant(size_t index) {
    if (current_variant_ == index) return;
    current_variant_ = index;
    frames_ = VariantFrames{};
    rest_.reset();
    if (references_.kept_variant == index) {
      frames_ = std::move(references_.kept_frames);
      references_.kept_variant.reset();
    } else {
      frames_ = variant_frames(experiment_, experiment_.variants.at(index), paths_);  // stored by the check: loaded
    }
  }

  std::string prepare(CausticMethod& method, const SceneVariant& variant, const RunSpec& first, PrepareOutcome& prepared) {
    try {
      auto zero = frames_.posed.find(0);
      const PosedFrame* frame_zero = zero == frames_.posed.end() ? nullptr : zero->second.get();
      prepared = prepare_method(method, prepare_context(variant.scene, experiment_.frames, frame_zero, rest_), first.build,
                                &builds_);
      if (!prepared.build_key.empty()) {
        fmt::print(stderr, "build {} of {}: {} ({:.3g} s to compute{})\n", prepared.build_key, first.method, prepared.source,
                   prepared.prepare_seconds,
                   prepared.source == "loaded" ? fmt::format(", {:.3g} s to load", prepared.load_seconds) : "");
      }
    } catch (const WriteError&) {
      throw;  // the store cannot be written: nothing further can be stored either
    } catch (...) {
      return current_exception_text();  // a plugin may throw anything
    }
    return "";
  }

  // Plays the claimed runs (one variant, method, build and frame knobs) with each of their seeds, the
  // run's own first; a seed that is a build knob gets its own prepare(). Each run is stored once all of
  // its seeds are measured (experiments/seed_replicas.h).
  void play(CausticMethod& method, const PrepareOutcome& prepared, const std::vector<ClaimedRun>& claimed) {
    const RunSpec& first = *claimed.front().run;
    auto empty = references_.empty.find(first.variant);
    const std::vector<FramePresence>& empty_reference = empty == references_.empty.end() ? scored_ : empty->second;
    const int seeds = seed_count(experiment_, first);
    std::vector<std::vector<RunOutcome>> outcomes(claimed.size());
    for (int s = 0; s < seeds; ++s) {
      std::vector<RunSpec> replicas;
      for (const ClaimedRun& run : claimed) replicas.push_back(seed_replica(*run.run, s));
      const std::string which = s == 0 ? "" : fmt::format("seed {}: ", replicas.front().params.integer("seed"));
      CausticMethod* instance = &method;
      const PrepareOutcome* instance_prepared = &prepared;
      std::unique_ptr<CausticMethod> own;
      PrepareOutcome own_prepared;
      if (s > 0 && replicas.front().build.has("seed")) {
        std::string error;
        try {
          own = create_method(first.method);
          error = prepare(*own, experiment_.variants.at(first.variant), replicas.front(), own_prepared);
        } catch (const MethodError& failure) {  // its constructor failed
          error = failure.what();
        }
        if (!error.empty()) {
          for (const ClaimedRun& run : claimed) fail(run, which + error);
          return;
        }
        instance = own.get();
        instance_prepared = &own_prepared;
      }
      std::vector<ParamSet> render_sets;
      for (const RunSpec& replica : replicas) render_sets.push_back(replica.render);
      std::vector<SequenceOutput> outputs;
      try {
        outputs = play_sequence(*instance, frames_.sequence(experiment_.frames), replicas.front().frame, render_sets,
                                TimingProtocol{true, experiment_.repetitions, experiment_.pixel_samples});
      } catch (const WriteError&) {
        throw;
      } catch (...) {
        for (const ClaimedRun& run : claimed) fail(run, which + current_exception_text());
        return;
      }
      for (size_t r = 0; r < claimed.size(); ++r) {
        try {
          outcomes[r].push_back(measure_run(experiment_, replicas[r], *instance, *instance_prepared, std::move(outputs[r]),
                                            frames_, empty_reference));
        } catch (const WriteError&) {
          throw;
        } catch (...) {
          RunOutcome failed;
          failed.record = run_identity(experiment_, replicas[r]);
          failed.record.status = "failed";
          failed.record.error = current_exception_text();  // combine_seeds names the seed
          outcomes[r].push_back(std::move(failed));
        }
      }
    }
    for (size_t r = 0; r < claimed.size(); ++r) {
      const RunSpec& run = *claimed[r].run;
      try {
        RunOutcome outcome = seeds > 1 ? combine_seeds(std::move(outcomes[r])) : std::move(outcomes[r].front());
        store_run(store_, claimed[r].claim, outcome);
        if (outcome.record.ok()) {
          ++summary_.completed;
          const std::optional<LostFluxRecord>& lost = outcome.record.lost_flux;
          if (lost && lost->worst.fraction > kLostFluxWarning)
            fmt::print(stderr, "warning: run {} {}\n", run.label, describe_lost_flux(lost->worst));
          // A warning, never a failure of the run it is about: stored already, it stays stored.
          try {
            warn_of_unexplained_light(run, outcome.record);
          } catch (const std::exception& error) {
            fmt::print(stderr, "warning: run {}: its light account could not be read: {}\n", run.label, error.what());
          }
        } else {
          ++summary_.failed;
          fmt::print(stderr, "run {} failed: {}\n", run.label, outcome.record.error);
        }
        progress_.update(static_cast<double>(++done_), run.label);
      } catch (const WriteError&) {
        throw;
      } catch (...) {
        fail(claimed[r], current_exception_text());
      }
    }
  }

  void fail(const ClaimedRun& claimed, const std::string& error) {
    const RunSpec& run = *claimed.run;
    store_failure(store_, claimed.claim, experiment_, run, error);
    ++summary_.failed;
    fmt::print(stderr, "run {} failed: {}\n", run.label, error);
    progress_.update(static_cast<double>(++done_), run.label);
  }

  const Experiment& experiment_;
  ResultStore& store_;
  const ResultPaths& paths_;
  std::map<std::string, nlohmann::json> reference_records_;  // reference key -> its record.json (null: none)
  BuildCacheFolder builds_;
  ReferenceCheck& references_;
  RunSummary& summary_;
  Progress progress_;
  size_t done_ = 0;
  std::optional<size_t> current_variant_;
  VariantFrames frames_;
  std::unique_ptr<RestPose> rest_;
  const std::vector<FramePresence> scored_;  // no frame with an empty reference
};

// Each pending run, and the reference of its variant, must fit in this machine's memory: a variant at
// 16384x16384, or lpi with multires_depth: 9, is refused with the estimate (naming the resolution or
// the knob) before any reference or run starts. Runs that share their knobs on a variant share a check.
void check_memory(const Experiment& experiment, const std::vector<PendingRun>& pending) {
  std::set<std::tuple<size_t, std::string, std::string>> checked;  // (variant, method, knobs)
  std::map<size_t, std::unique_ptr<RestPose>> rests;                // a variant's rest pose, built once
  auto check = [&](size_t index, const std::string& method, const ParamSet& knobs, int pixel_samples) {
    if (!checked.insert({index, method, knobs.to_json().dump()}).second) return;
    const SceneVariant& variant = experiment.variants.at(index);
    std::unique_ptr<RestPose>& rest = rests[index];
    if (!rest) rest = std::make_unique<RestPose>(variant.scene, experiment.frames);
    const Camera& camera = variant.scene.camera;
    try {
      const std::unique_ptr<CausticMethod> instance = create_method(method);
      check_memory_fits(estimate_run_memory(camera.width, camera.height, *instance, rest->context(), knobs, pixel_samples),
                        fmt::format("{}: variant {} with {} at {}x{}", experiment.source, variant.name, method,
                                    camera.width, camera.height));
    } catch (const MethodError& error) {
      // A method's own code failed (a plugin's constructor or knob_memory() threw): its runs record that
      // when they are played; the others go ahead.
      fmt::print(stderr, "warning: the memory of {}'s runs cannot be estimated: {}\n", method, error.what());
    }
  };
  for (const PendingRun& entry : pending) {
    check(entry.run->variant, "reference", experiment.reference_params, 1);  // the reference averages footprints itself
    check(entry.run->variant, entry.run->method, entry.run->params, experiment.pixel_samples);
  }
}

std::vector<const RunSpec*> specs(const std::vector<PendingRun>& pending) {
  std::vector<const RunSpec*> result;
  for (const PendingRun& entry : pending) result.push_back(entry.run);
  return result;
}

}  // namespace

RunSummary run_experiment(const Experiment& experiment, const RunOptions& given_options) {
  RunOptions options = given_options;
  if (options.shard_count > 1 && options.shard_of.empty()) {
    options.shard_of = plan_shards(experiment, options.shard_count, nullptr).shard_of;
  }
  ResultPaths paths{options.results};
  RunSummary summary;
  summary.total = experiment.runs.size();
  const std::string folder = paths.experiment(experiment.name);
  const std::string runs_folder = (fs::path(folder) / "runs").string();
  // What killed processes left is finished or undone first: a replacement interrupted between its two
  // renames must not make its run look pending (core/staging_folder.h).
  remove_stale_staging(runs_folder);
  ResultStore store(paths, experiment.name, experiment.frames);
  RunSelection selection = select_runs(experiment, options, store);
  summary.selected = selection.selected;
  // What this machine cannot hold is refused before anything else, --dry-run included.
  check_memory(experiment, selection.pending);
  if (options.dry_run) {
    summary.stored = selection.stored;
    return summary;
  }

  // Every reference is computed (or loaded) and checked before any run starts, and before anything is
  // written into the experiment's folder: an empty reference stops here with nothing of it changed.
  ReferenceCheck references = check_references(experiment, specs(selection.pending), paths);
  std::vector<size_t> checked_variants;
  for (const PendingRun& entry : selection.pending) checked_variants.push_back(entry.run->variant);
  recheck_against_references(experiment, checked_variants, store, selection);
  summary.stored = selection.stored;
  if (options.prepare_only) {
    BuildSummary builds = prepare_missing_builds(experiment, specs(selection.pending), paths);
    summary.builds_computed = builds.computed;
    summary.builds_stored = builds.stored;
    return summary;
  }

  make_folders(runs_folder);
  remove_stale_partial_files(folder);
  nlohmann::json environment = environment_json(options.threads);
  environment["experiment"] = experiment.name;
  write_text_atomically((fs::path(folder) / "environment.json").string(), environment.dump(2) + "\n");
  write_text_atomically((fs::path(folder) / "experiment.json").string(), experiment.to_json().dump(2) + "\n");

  RunExecutor executor(experiment, store, references, summary, selection.pending.size());
  std::vector<PendingRun> to_do = std::move(selection.pending);
  while (!to_do.empty()) {
    std::vector<PendingRun> held_by_others = executor.execute(to_do);
    to_do.clear();
    // Each waited for in turn, holding no other lock meanwhile (so that no two processes wait for each
    // other); one whose holder ended without storing it is run here after all.
    for (const PendingRun& pending : held_by_others) {
      // The claim is given up again at once: the run is claimed anew with the others of its batch.
      if (store.claim(run_address(experiment, *pending.run), pending.seen, pending.replace_stored)) to_do.push_back(pending);
      else executor.stored_by_another(*pending.run);
    }
  }
  executor.finish();
  return summary;
}

}  // namespace causticbench
