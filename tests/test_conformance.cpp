// Conformance of every registered method to the interface (methods/method.h), parameterised over the
// registry so that a new method is covered without editing this file: its knobs resolve and its README
// opens with `describe --markdown`; its output is well formed on every shipped scene it accepts; the
// same seed gives the same output on 1 and 2 threads; one prepared instance rendering several knob
// sets equals fresh instances; a saved and loaded build renders identically. The capability matrix is
// measured in test_capabilities.cpp.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/files.h"
#include "core/image_statistics.h"
#include "core/parallel.h"
#include "store/build_cache.h"
#include "methods/describe.h"
#include "methods/frame_dump.h"
#include "methods/lifecycle.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;
using testing::kSmallGlassSphere;
using testing::scene_from_yaml;

class Conformance : public ::testing::TestWithParam<std::string> {
 protected:
  const MethodInfo& info() const { return find_method(GetParam()).info(); }

  // The method's quick knobs with `extra` on top, resolved.
  ParamSet knobs(const std::vector<std::string>& extra = {}) const {
    ParamDict dict;
    for (const std::string& knob : info().quick_knobs) dict.set_assignment(knob, "quick_knobs");
    for (const std::string& knob : extra) dict.set_assignment(knob, "test");
    return dict.resolve(info().params, info().name);
  }
};

bool bitwise_equal(const Image& a, const Image& b) {
  return a.width() == b.width() && a.height() == b.height() && a.channels() == b.channels() &&
         std::memcmp(a.values().data(), b.values().data(), a.values().size() * sizeof(float)) == 0;
}

// One prepared instance, updated and rendered on one posed frame.
struct Prepared {
  std::unique_ptr<CausticMethod> method;
  std::unique_ptr<RestPose> rest;
  std::unique_ptr<PosedFrame> posed;
  Prepared(const Scene& scene, const std::string& name, const ParamSet& all, const std::string& cache = "")
      : method(create_method(name)), rest(std::make_unique<RestPose>(scene, std::vector<int>{0})),
        posed(std::make_unique<PosedFrame>(scene, 0)) {
    std::optional<BuildCacheFolder> builds;
    if (!cache.empty()) builds.emplace(cache);
    prepare_method(*method, rest->context(), split_phases(all, method->info().params).build, builds ? &*builds : nullptr);
  }
  Image render(const ParamSet& all) {
    PhaseKnobs phases = split_phases(all, method->info().params);
    return std::move(play_sequence(*method, {posed.get()}, phases.frame, {phases.render}, TimingProtocol{false, 1})
                         .front()
                         .images.front());
  }
};

Image fresh_render(const Scene& scene, const std::string& name, const ParamSet& all) {
  return Prepared(scene, name, all).render(all);
}

TEST_P(Conformance, DefaultsAndQuickKnobsResolve) {
  ParamSet defaults = ParamDict{}.resolve(info().params, info().name);
  std::vector<std::string> earlier;
  for (const ParamSpec& spec : info().params) {
    if (spec.applies_when) {
      // A condition names an earlier choice or boolean knob and values it can take.
      const ParamSpec* control = nullptr;
      for (const ParamSpec& candidate : info().params) {
        if (candidate.name == spec.applies_when->knob) control = &candidate;
      }
      ASSERT_NE(control, nullptr) << spec.name << " applies when an undeclared knob " << spec.applies_when->knob;
      EXPECT_NE(std::find(earlier.begin(), earlier.end(), control->name), earlier.end())
          << spec.name << ": its condition's knob must be declared before it";
      for (const std::string& value : spec.applies_when->values) {
        bool possible = control->type == causticbench::ParamType::boolean ? (value == "true" || value == "false")
                                                            : std::count(control->choices.begin(), control->choices.end(), value) > 0;
        EXPECT_TRUE(control->type == causticbench::ParamType::choice || control->type == causticbench::ParamType::boolean) << spec.name;
        EXPECT_TRUE(possible) << spec.name << ": " << control->name << " cannot be " << value;
      }
    } else if (!spec.family) {
      EXPECT_TRUE(defaults.has(spec.name)) << spec.name;
    }
    if (spec.type == causticbench::ParamType::choice) {
      EXPECT_NE(std::find(spec.choices.begin(), spec.choices.end(), std::get<std::string>(spec.default_value)),
                spec.choices.end())
          << spec.name;
    }
    EXPECT_FALSE(spec.meaning.empty()) << spec.name;
    earlier.push_back(spec.name);
  }
  EXPECT_NO_THROW(knobs()) << "quick_knobs of " << info().name;
}

TEST_P(Conformance, ReadmeOpensWithDescribeMarkdown) {
  if (find_method(GetParam()).plugin) GTEST_SKIP() << "a plugin's README lives with the plugin, not in this tree";
  std::string path = std::string(CAUSTICBENCH_SOURCE_DIR) + "/methods/" + info().name + "/README.md";
  ASSERT_TRUE(fs::is_regular_file(path)) << path;
  std::string readme = read_text(path), generated = describe_markdown(info());
  EXPECT_EQ(readme.substr(0, generated.size()), generated)
      << path << " must open with `causticbench describe " << info().name << " --markdown`; regenerate it";
}

TEST_P(Conformance, CapabilityNotesNameRealCapabilities) {
  std::vector<std::string> names;
  for (const auto& [name, value] : info().capabilities.entries()) names.push_back(name);
  for (const auto& [name, note] : info().capabilities.notes) {
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << "note on unknown capability " << name;
    EXPECT_FALSE(note.empty()) << name;
  }
}

// A method with the GpuBackend facet can dump its frame only if its folder registered the replay that
// gpubench reads it with (causticbench_add_gpu_backend), and a registered replay belongs to such a method.
TEST_P(Conformance, GpuBackendFacetMatchesTheReplayFormats) {
  if (find_method(GetParam()).plugin) GTEST_SKIP() << "a plugin registers no replay for causticbench-gpubench";
  bool listed = false;
  for (const FrameDumpFormat& format : frame_dump_formats()) listed = listed || format.method == info().name;
  EXPECT_EQ(create_method(info().name)->gpu() != nullptr, listed)
      << "the GpuBackend facet and the formats registered by causticbench_add_gpu_backend disagree";
}

// Output has the G-buffer's size, is finite and non-negative, and zero off the receivers, on every
// shipped scene the method accepts (check_scene or prepare refuses the others with an InputError).
TEST_P(Conformance, OutputIsWellFormedOnEveryShippedSceneItAccepts) {
  size_t accepted = 0;
  for (const auto& entry : fs::directory_iterator(testing::shipped_scenes())) {
    if (entry.path().extension() != ".yaml") continue;
    Scene scene = load_scene(entry.path().string());
    set_resolution(scene, 24, 18);
    FrameResult result;
    try {
      result = testing::render(scene, info().name, info().quick_knobs);
    } catch (const InputError& refused) {
      continue;
    }
    ++accepted;
    const std::string where = info().name + " on " + entry.path().filename().string();
    ASSERT_EQ(result.caustic.width(), result.gbuffer.width) << where;
    ASSERT_EQ(result.caustic.height(), result.gbuffer.height) << where;
    ASSERT_EQ(result.caustic.channels(), 3) << where;
    size_t bad = 0, lit_off_receiver = 0;
    for (size_t pixel = 0; pixel < result.gbuffer.pixel_count(); ++pixel) {
      for (int c = 0; c < 3; ++c) {
        float value = result.caustic.at(pixel, c);
        bad += !std::isfinite(value) || value < 0.0f;
        lit_off_receiver += !result.gbuffer.receiver[pixel] && value != 0.0f;
      }
    }
    std::set<std::string> reported, declared;
    for (const auto& [name, value] : result.counters) reported.insert(name);
    for (const QuantityInfo& counter : info().counters) declared.insert(counter.name);
    EXPECT_EQ(reported, declared) << where << ": counters() must report exactly MethodInfo::counters (the quantity "
                                              "registry's list of what claims, tables and plots may use)";
    EXPECT_EQ(bad, 0u) << where << ": non-finite or negative values";
    EXPECT_EQ(lit_off_receiver, 0u) << where << ": values off the receivers";
  }
  EXPECT_GT(accepted, 0u) << info().name << " accepts no shipped scene";
}

TEST_P(Conformance, SameSeedSameOutputOnOneAndTwoThreads) {
  Scene scene = scene_from_yaml(kSmallGlassSphere);
  FrameResult one, two;
  {
    ThreadLimit limit(1);
    one = testing::render(scene, info().name, info().quick_knobs);
  }
  {
    ThreadLimit limit(2);
    two = testing::render(scene, info().name, info().quick_knobs);
  }
  EXPECT_TRUE(bitwise_equal(one.caustic, two.caustic)) << info().name << " differs between 1 and 2 threads";
  // Equal images prove nothing when both are black: the glass ball under the sun has a caustic in view.
  EXPECT_GT(masked_sum(one.caustic, one.gbuffer.receiver), 0.0) << info().name << " renders no caustic";
}

// Another valid value of a knob (the next choice, the other boolean, a larger or smaller number), or
// nothing when there is none that leaves the run deterministic (a zero time or noise target).
std::optional<std::string> other_value(const ParamSpec& spec, const ParamValue& current) {
  switch (spec.type) {
    case causticbench::ParamType::boolean: return std::get<bool>(current) ? "false" : "true";
    case causticbench::ParamType::choice: {
      auto it = std::find(spec.choices.begin(), spec.choices.end(), std::get<std::string>(current));
      return spec.choices[(it - spec.choices.begin() + 1) % spec.choices.size()];
    }
    case causticbench::ParamType::text: return std::nullopt;  // no other text known to be valid
    case causticbench::ParamType::integer:
    case causticbench::ParamType::real: {
      // A numeric knob at `auto` (ParamSpec::auto_by_default): any number in its range is another value.
      if (std::holds_alternative<std::string>(current)) return fmt::format("{}", std::clamp(1.0, spec.min_value, spec.max_value));
      double value = spec.type == causticbench::ParamType::integer ? static_cast<double>(std::get<int64_t>(current)) : std::get<double>(current);
      if (value == 0.0) return std::nullopt;
      for (double factor : {2.0, 0.5}) {
        double other = spec.type == causticbench::ParamType::integer ? std::round(value * factor) : value * factor;
        if (other != value && other >= spec.min_value && other <= spec.max_value) return fmt::format("{}", other);
      }
      return std::nullopt;
    }
  }
  return std::nullopt;
}

// One prepare(), then update/render with each frame and render knob changed in turn (and the base set
// again in between, to catch state that leaks from one knob set to the next), equals a fresh instance
// per knob set, bit for bit.
TEST_P(Conformance, OnePreparedInstanceEqualsFreshInstancesForEveryKnobSet) {
  Scene scene = scene_from_yaml(kSmallGlassSphere);
  const ParamSet base = knobs();
  std::vector<ParamSet> sets;
  for (const ParamSpec& spec : info().params) {
    if (spec.phase == ParamPhase::build || !base.has(spec.name)) continue;
    std::optional<std::string> other = other_value(spec, base.values().at(spec.name));
    if (!other) continue;
    try {
      sets.push_back(knobs({spec.name + "=" + *other}));
      sets.push_back(base);
    } catch (const InputError&) {
      // The other value switches off a knob that is set in quick_knobs; nothing to compare.
    }
  }
  if (sets.empty()) GTEST_SKIP() << info().name << " has no frame or render knobs";
  Prepared shared(scene, info().name, base);
  double largest = 0.0;
  for (const ParamSet& set : sets) {
    Image from_shared = shared.render(set);
    Image from_fresh = fresh_render(scene, info().name, set);
    EXPECT_TRUE(bitwise_equal(from_shared, from_fresh)) << info().name << " with " << set.to_json().dump();
    largest = std::max(largest, masked_sum(from_fresh, shared.posed->gbuffer.receiver));
  }
  EXPECT_GT(largest, 0.0) << info().name << ": every compared image is black, so their equality says nothing";
}

// A method whose build is cacheable on a scene: a saved and loaded build renders bit-identically,
// through prepare_method's cache the second prepare loads, and the build's dependencies ignore the
// camera but not the build knobs.
TEST_P(Conformance, SavedAndLoadedBuildRendersIdentically) {
  Scene scene = scene_from_yaml(kSmallGlassSphere);
  const ParamSet all = knobs();
  const PhaseKnobs phases = split_phases(all, info().params);
  std::unique_ptr<CausticMethod> probe = create_method(info().name);
  RestPose rest(scene, {0});
  BuildCache* probe_cache = probe->build_cache();
  if (!probe_cache) GTEST_SKIP() << info().name << " has no build cache facet";
  std::optional<nlohmann::json> dependencies = probe_cache->build_dependencies(rest.context(), phases.build);
  if (!dependencies) GTEST_SKIP() << info().name << " stores no build for this scene";

  fs::path cache = fs::temp_directory_path() / ("causticbench_conformance_builds_" + info().name);
  fs::remove_all(cache);
  Prepared computed(scene, info().name, all, cache.string());
  Image first = computed.render(all);
  Prepared loaded(scene, info().name, all, cache.string());
  Image second = loaded.render(all);
  EXPECT_TRUE(bitwise_equal(first, second)) << "a loaded build must render as the computed one";
  std::unique_ptr<CausticMethod> check = create_method(info().name);
  BuildCacheFolder builds(cache.string());
  EXPECT_EQ(prepare_method(*check, rest.context(), phases.build, &builds).source, "loaded");

  // A different camera and resolution: the same build.
  Scene moved = scene_from_yaml(testing::replace_once(
      testing::replace_once(kSmallGlassSphere, "position: [0, 2.0, 2.0]", "position: [1, 3.0, 1.0]"), "resolution: [40, 40]",
      "resolution: [30, 20]"));
  RestPose moved_rest(moved, {0});
  EXPECT_EQ(probe_cache->build_dependencies(moved_rest.context(), phases.build), dependencies);
  // A different glass: a different build.
  Scene other_glass = scene_from_yaml(testing::replace_once(kSmallGlassSphere, "ior: 1.5", "ior: 1.4"));
  RestPose other_rest(other_glass, {0});
  std::optional<nlohmann::json> other = probe_cache->build_dependencies(other_rest.context(), phases.build);
  if (other) {
    EXPECT_NE(build_cache_key(info().name, *other), build_cache_key(info().name, *dependencies));
  }
  // A different value of each build knob: a different build.
  for (const ParamSpec& spec : info().params) {
    if (spec.phase != ParamPhase::build || !all.has(spec.name)) continue;
    std::optional<std::string> value = other_value(spec, all.values().at(spec.name));
    if (!value) continue;
    ParamSet changed = split_phases(knobs({spec.name + "=" + *value}), info().params).build;
    std::optional<nlohmann::json> changed_dependencies = probe_cache->build_dependencies(rest.context(), changed);
    if (changed_dependencies) {
      EXPECT_NE(*changed_dependencies, *dependencies) << spec.name;
    }
  }
  // A damaged stored build is recomputed, with a warning, and replaced.
  std::string key = build_cache_key(info().name, *dependencies);
  size_t damaged = 0;
  for (const auto& entry : fs::directory_iterator(cache / key)) {
    if (entry.path().filename() == "build.json") continue;
    std::ofstream(entry.path(), std::ios::trunc) << "damaged";
    ++damaged;
  }
  if (damaged == 0) return;  // a build that is all in build.json: nothing to damage
  std::unique_ptr<CausticMethod> repaired = create_method(info().name);
  PrepareOutcome outcome = prepare_method(*repaired, rest.context(), phases.build, &builds);
  EXPECT_EQ(outcome.source, "recomputed");
  EXPECT_FALSE(outcome.warning.empty());
  Prepared after_repair(scene, info().name, all, cache.string());
  EXPECT_TRUE(bitwise_equal(after_repair.render(all), first));
  fs::remove_all(cache);
}

INSTANTIATE_TEST_SUITE_P(Registry, Conformance, ::testing::ValuesIn(native_method_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace causticbench
