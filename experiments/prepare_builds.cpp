#include "experiments/prepare_builds.h"

#include <map>
#include <memory>
#include <set>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/progress.h"
#include "experiments/seed_replicas.h"
#include "store/build_cache.h"
#include "methods/lifecycle.h"
#include "methods/registry.h"

namespace causticbench {

BuildSummary prepare_missing_builds(const Experiment& experiment, const std::vector<const RunSpec*>& runs,
                                    const ResultPaths& paths) {
  BuildSummary summary;
  // One run per group, variant by variant so that one rest pose is kept at a time.
  std::map<std::pair<size_t, std::string>, const RunSpec*> groups;
  // A seed that is a build knob: every seed the runs are measured with has a build of its own.
  std::vector<std::unique_ptr<RunSpec>> replicas;
  for (const RunSpec* run : runs) {
    groups.insert({{run->variant, run->method + run->build.to_json().dump()}, run});
    if (!run->build.has("seed")) continue;
    for (int s = 1; s < seed_count(experiment, *run); ++s) {
      replicas.push_back(std::make_unique<RunSpec>(seed_replica(*run, s)));
      groups.insert({{run->variant, run->method + replicas.back()->build.to_json().dump()}, replicas.back().get()});
    }
  }
  Progress progress("builds of " + experiment.name, static_cast<double>(groups.size()));
  std::set<std::string> seen_keys;  // a build serves every variant: computed once
  BuildCacheFolder builds(paths.builds());
  std::unique_ptr<RestPose> rest;
  size_t rest_variant = SIZE_MAX, done = 0;
  for (const auto& [group, run] : groups) {
    const SceneVariant& variant = experiment.variants.at(run->variant);
    if (rest_variant != run->variant) {
      rest.reset();
      rest_variant = run->variant;
    }
    try {
      std::unique_ptr<CausticMethod> method = create_method(run->method);
      PrepareContext context = prepare_context(variant.scene, experiment.frames, nullptr, rest);
      method->check_scene(variant.scene);
      BuildCache* cache = method->build_cache();
      std::optional<nlohmann::json> dependencies;
      if (cache) dependencies = cache->build_dependencies(context, run->build);
      if (!dependencies) {
        ++summary.uncached;
      } else {
        std::string key = build_cache_key(run->method, *dependencies);
        std::optional<StoredBuild> stored = find_stored_build(paths.builds(), key, run->method, *dependencies);
        if (!seen_keys.insert(key).second || (stored && stored->problem.empty())) {
          ++summary.stored;
        } else {
          PrepareOutcome outcome = prepare_method(*method, context, run->build, &builds);
          fmt::print(stderr, "build {} of {}: {} ({:.3g} s)\n", outcome.build_key, run->method, outcome.source,
                     outcome.prepare_seconds);
          ++summary.computed;
        }
      }
    } catch (const WriteError&) {
      throw;
    } catch (...) {
      // Not this job's to record: the shard that runs the group stores the failure in each run's record.
      fmt::print(stderr, "warning: prepare() of {} ({}) failed: {}; its runs will record the failure\n", run->method,
                 run->label, current_exception_text());
      ++summary.failed;
    }
    progress.update(static_cast<double>(++done), run->label);
  }
  progress.finish(fmt::format("{} builds computed, {} stored already, {} not cached", summary.computed, summary.stored,
                              summary.uncached));
  return summary;
}

}  // namespace causticbench
