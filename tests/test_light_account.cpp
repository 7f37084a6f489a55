// Issue 52, item 4: the light account (experiments/light_account.h) against a method that lies about what
// it models. Two synthetic methods render nothing on the small glass sphere, whose caustic in view is ~96 %
// one pass through the ball and ~3 % reflected off it (methods/reference/tests/test_reference_path_classes.cpp):
//   - "declares_refraction" says it models reflection, refraction and multiple bounces: its
//     missing light is nothing it declares, so the account leaves ~all of it unexplained and flags it, in
//     the runner's warning and in the report's findings and results table;
//   - "declares_reflection_only" says it models reflection only: the ~96 % in the one-pass class is its
//     declared model share, the ~3 % it misses is within the tolerance, and nothing is flagged.
// Both are black, so the difference is only what they declare: the flag reads the declarations against the
// reference's split, not the image.
#include <filesystem>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "experiments/experiment.h"
#include "experiments/light_account.h"
#include "experiments/runner.h"
#include "methods/registry.h"
#include "reports/report.h"
#include "reports/summary.h"
#include "tests/report_test_support.h"
#include "tests/test_support.h"

using namespace causticbench;

namespace {

template <bool kRefraction>
class DarkMethod : public CausticMethod {
 public:
  static const MethodInfo& static_info() {
    static const MethodInfo info = [] {
      MethodInfo m;
      m.name = kRefraction ? "declares_refraction" : "declares_reflection_only";
      m.paper = "none (a test fixture)";
      m.summary = "renders no caustic";
      m.capabilities.reflection = true;
      m.capabilities.refraction = kRefraction;
      m.capabilities.multiple_bounces = kRefraction;  // the ball's light after internal reflections (0.2 %)
      m.capabilities.directional_light = true;
      return m;
    }();
    return info;
  }
  const MethodInfo& info() const override { return static_info(); }
  void prepare(const PrepareContext&, const ParamSet&) override {}
  void update(const FrameContext&, const ParamSet&) override {}
  Image render(const GBuffer& gbuffer, const ParamSet&) override { return Image(gbuffer.width, gbuffer.height, 3, 0.0f); }
  size_t memory_bytes() const override { return 0; }
  Counters counters() const override { return {}; }
};

}  // namespace

TEST(LightAccount, FlagsAMethodThatDeclaresACapabilityItLacks) {
  ScopedMethodRegistration liar({&DarkMethod<true>::static_info, [] { return std::make_unique<DarkMethod<true>>(); }});
  ScopedMethodRegistration honest({&DarkMethod<false>::static_info, [] { return std::make_unique<DarkMethod<false>>(); }});
  causticbench::testing::TemporaryFolder folder("light_account");
  folder.write("scene.yaml", causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                                 "resolution: [40, 40]", "resolution: [24, 24]"));
  const Experiment experiment = load_experiment(folder.write("accounts.yaml", R"(name: accounts
scene: scene.yaml
reference: {photons_per_pass: 200000, max_passes: 2, target_error: 0}
repetitions: 1
metrics: [relmse, energy_ratio]
methods:
  - method: declares_refraction
  - method: declares_reflection_only
)"));
  RunOptions options;
  options.results = folder.path("results");
  ::testing::internal::CaptureStderr();
  const RunSummary summary = run_experiment(experiment, options);
  const std::string printed = ::testing::internal::GetCapturedStderr();
  ASSERT_EQ(summary.completed, 2u) << printed;

  // The runner's one-line warning names the liar only.
  EXPECT_NE(printed.find("warning: run declares_refraction unexplained: 1.00 of the light missing, not a declared limit"),
            std::string::npos)
      << printed;
  EXPECT_EQ(printed.find("warning: run declares_reflection_only"), std::string::npos) << printed;

  // The accounts themselves, from the stored records against the reference's split.
  const std::string results = options.results + "/accounts";
  const nlohmann::json experiment_json = nlohmann::json::parse(report_testing::read_text(results + "/experiment.json"));
  std::optional<LightAccount> lying, declared;
  for (const auto& entry : std::filesystem::directory_iterator(results + "/runs")) {
    const RunRecord record = RunRecord::from_json(nlohmann::json::parse(report_testing::read_text((entry.path() / "record.json").string())));
    const nlohmann::json reference =
        nlohmann::json::parse(report_testing::read_text(options.results + "/references/" + record.reference_key + "/record.json"));
    (record.method == "declares_refraction" ? lying : declared) = account_for_record(reference, record);
  }
  ASSERT_TRUE(lying && declared);
  EXPECT_EQ(lying->energy, 0.0);
  EXPECT_EQ(lying->model, 0.0) << "it declares everything the sphere's light needs";
  EXPECT_NEAR(lying->unexplained, 1.0, 1e-12);
  EXPECT_TRUE(lying->flagged);
  EXPECT_GT(declared->model, 0.9) << "the one-pass class: refraction, which it declares it lacks";
  EXPECT_LT(declared->unexplained, kUnexplainedLightTolerance) << "the light reflected off the ball, ~3 %";
  EXPECT_FALSE(declared->flagged);

  // The report says the same beside the scores.
  const ReportSummary report = write_report(results);
  const std::string md = report_testing::read_text(report.markdown);
  EXPECT_NE(md.find("Light not accounted for: **declares_refraction**"), std::string::npos) << md;
  EXPECT_EQ(md.find("Light not accounted for: **declares_reflection_only**"), std::string::npos) << md;
  EXPECT_NE(md.find("(100 % of the light unexplained)"), std::string::npos) << md;
  EXPECT_NE(md.find("model): declares_reflection_only does not model 9"), std::string::npos) << md;
  // results.json: the run's account and its one frame's, the same here.
  for (const nlohmann::json& run : nlohmann::json::parse(report_testing::read_text(report.json)).at("runs")) {
    const nlohmann::json& account = run.at("light_account");
    ASSERT_EQ(account.at("frames").size(), 1u) << account.dump();
    EXPECT_EQ(account["frames"][0]["frame"], 0);
    EXPECT_DOUBLE_EQ(account["frames"][0]["unexplained"].get<double>(), account["unexplained"].get<double>());
    EXPECT_EQ(account["flagged"], run.at("method") == "declares_refraction");
  }

  // The study's summary says where each fails from the same accounts.
  const SummaryFiles files = write_summary({results}, folder.path("summary"));
  const nlohmann::json study = nlohmann::json::parse(report_testing::read_text(files.json));
  std::map<std::string, std::set<std::string>> kinds;
  for (const nlohmann::json& method : study.at("methods"))
    for (const nlohmann::json& failure : method.at("failures")) kinds[method.at("method")].insert(failure.at("kind"));
  EXPECT_TRUE(kinds["declares_refraction"].count("light unexplained")) << study.dump(2);
  EXPECT_FALSE(kinds["declares_refraction"].count("not modelled"));
  EXPECT_TRUE(kinds["declares_reflection_only"].count("not modelled")) << study.dump(2);
  EXPECT_FALSE(kinds["declares_reflection_only"].count("light unexplained"));
}

// Occlusion (issue 52): a method that does not model occlusion may put out the light occluders block, the
// reference's occlusion "excess" in view, beyond the reference. On a split whose occluders block 0.39 of
// the light that arrives (the occlusion capability case measures 0.387), an energy of 1.39 is within the
// account of a method that declares occlusion false and 0.39 in excess, flagged, for one that declares it
// true; both are within it at energy 1. A split written before occlusion was measured raises no excess.
TEST(LightAccount, AMethodWithoutOcclusionMayAddTheLightOccludersBlock) {
  nlohmann::json split = {{"path_classes",
                           {{"in_view",
                             {{"flux", 1.0},
                              {"joint", {{"one_reflection/directional/lambertian",
                                          {{"share", 1.0}, {"capabilities", {"reflection", "directional_light"}}}}}},
                              {"occlusion", {{"share", 0.39 / 1.39}, {"excess", 0.39}}}}}}}};
  Capabilities without;
  without.reflection = without.directional_light = true;
  Capabilities with = without;
  with.occlusion = true;
  const std::optional<LightAccount> lets_through = account_for_light(split, without, 1.39, 0.0);
  ASSERT_TRUE(lets_through);
  EXPECT_DOUBLE_EQ(lets_through->excess, 0.39);
  EXPECT_DOUBLE_EQ(lets_through->unexplained, 0.0);
  EXPECT_FALSE(lets_through->flagged);
  EXPECT_NE(describe_light_account(*lets_through).find("39.0 % that occluders block"), std::string::npos);
  const std::optional<LightAccount> claims = account_for_light(split, with, 1.39, 0.0);
  ASSERT_TRUE(claims);
  EXPECT_DOUBLE_EQ(claims->excess, 0.0);
  EXPECT_NEAR(claims->unexplained, -0.39, 1e-12);
  EXPECT_TRUE(claims->flagged);
  EXPECT_FALSE(account_for_light(split, with, 1.0, 0.0)->flagged);
  EXPECT_FALSE(account_for_light(split, without, 1.0, 0.0)->flagged);
  split["path_classes"]["in_view"].erase("occlusion");
  EXPECT_TRUE(account_for_light(split, without, 1.39, 0.0)->flagged);
}

// A light of a kind the method does not model (issue 52): pinhole, lpi and prt run the point-light case with
// a distant light in its place and put out 3.4 times the reference's energy there (tests/test_capabilities.cpp
// prints it). That energy is the substitute's, so beyond the tolerance the account bounds it below only; a
// sliver of such light (0.1 of it, below the tolerance) explains no excess of 0.5.
TEST(LightAccount, ALightKindTheMethodDoesNotModelLeavesItsEnergyUnboundedAbove) {
  auto split_with_point_share = [](double point) {
    nlohmann::json joint = {{"one_reflection/point/lambertian",
                             {{"share", point}, {"capabilities", {"reflection", "point_light"}}}}};
    if (point < 1.0)
      joint["one_reflection/directional/lambertian"] = {{"share", 1.0 - point},
                                                        {"capabilities", {"reflection", "directional_light"}}};
    return nlohmann::json{{"path_classes", {{"in_view", {{"flux", 1.0}, {"joint", joint}}}}}};
  };
  Capabilities distant_only;
  distant_only.reflection = distant_only.directional_light = true;
  const std::optional<LightAccount> substitute = account_for_light(split_with_point_share(1.0), distant_only, 3.4, 0.0);
  ASSERT_TRUE(substitute);
  EXPECT_DOUBLE_EQ(substitute->substituted, 1.0);
  EXPECT_DOUBLE_EQ(substitute->unexplained, 0.0);
  EXPECT_FALSE(substitute->flagged);
  EXPECT_NE(describe_light_account(*substitute).find("replaces the 100.0 %"), std::string::npos);
  const std::optional<LightAccount> sliver = account_for_light(split_with_point_share(0.1), distant_only, 1.5, 0.0);
  ASSERT_TRUE(sliver);
  EXPECT_NEAR(sliver->unexplained, -0.5, 1e-12);
  EXPECT_TRUE(sliver->flagged);
  Capabilities point_too = distant_only;
  point_too.point_light = true;
  EXPECT_TRUE(account_for_light(split_with_point_share(1.0), point_too, 3.4, 0.0)->flagged);
}

// Moved light (LostFlux::moved, issue 52): csl's point-focus spot lights move a torus's ring of light rather
// than drop it, so it may still land in view. Of a lost flux of 0.6, 0.55 moved: an energy of 0.95 is within
// the account (the moved light delivered in view after all), but in excess by 0.55 if all 0.6 were dropped.
TEST(LightAccount, MovedLightMayStillBeDelivered) {
  const nlohmann::json split = {
      {"path_classes",
       {{"in_view",
         {{"flux", 1.0},
          {"joint", {{"one_pass/directional/lambertian", {{"share", 1.0}, {"capabilities", {"refraction", "directional_light"}}}}}}}}}}};
  Capabilities glass;
  glass.refraction = glass.directional_light = true;
  const std::optional<LightAccount> moved = account_for_light(split, glass, 0.95, 0.6, 0.55);
  ASSERT_TRUE(moved);
  EXPECT_DOUBLE_EQ(moved->unexplained, 0.0);
  EXPECT_FALSE(moved->flagged);
  EXPECT_NEAR(account_for_light(split, glass, 0.95, 0.6, 0.0)->unexplained, -0.55, 1e-12);
  EXPECT_TRUE(account_for_light(split, glass, 0.95, 0.6, 0.0)->flagged);
  EXPECT_NEAR(account_for_light(split, glass, 0.2, 0.6, 0.55)->unexplained, 0.2, 1e-12) << "below 1 - lost";
}
