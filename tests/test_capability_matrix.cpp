// The capability matrix (issue 14, item 3): the verdict rule of experiments/capability_verdict.h on
// synthetic values, the report's matrix (reports/capability_matrix.h) built from synthetic records, and
// configs/experiments/study_capabilities.yaml read and checked like every experiment. Runs nothing: the
// cases themselves are rendered by tests/test_capabilities.cpp.
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "experiments/capability_verdict.h"
#include "experiments/experiment.h"
#include "reports/capability_matrix.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

using nlohmann::json;

TEST(CapabilityVerdictRule, JudgesSyntheticValues) {
  EXPECT_EQ(judge_capability(false, 1.0, 0.0), CapabilityVerdict::holds);
  EXPECT_EQ(judge_capability(false, 1.15, 0.25), CapabilityVerdict::holds);  // the bounds hold
  EXPECT_EQ(judge_capability(false, 0.86, 0.1), CapabilityVerdict::holds);
  EXPECT_EQ(judge_capability(false, 1.2, 0.1), CapabilityVerdict::neither);  // between hold and wrong
  EXPECT_EQ(judge_capability(false, 1.0, 0.4), CapabilityVerdict::neither);
  EXPECT_EQ(judge_capability(false, 1.31, 0.1), CapabilityVerdict::wrong);
  EXPECT_EQ(judge_capability(false, 0.0, 0.04), CapabilityVerdict::wrong);  // light missing, small relMSE
  EXPECT_EQ(judge_capability(false, 1.0, 0.51), CapabilityVerdict::wrong);
  EXPECT_EQ(judge_capability(false, NAN, 0.1), CapabilityVerdict::wrong);
  EXPECT_EQ(judge_capability(false, 1.0, std::nullopt), CapabilityVerdict::wrong);
  EXPECT_EQ(judge_capability(true, 1.0, 0.0), CapabilityVerdict::refused);  // values of a refusal are ignored

  EXPECT_TRUE(capability_verdict_agrees(true, CapabilityVerdict::holds));
  EXPECT_FALSE(capability_verdict_agrees(true, CapabilityVerdict::wrong));  // a disagreement
  EXPECT_FALSE(capability_verdict_agrees(true, CapabilityVerdict::refused));
  EXPECT_TRUE(capability_verdict_agrees(false, CapabilityVerdict::wrong));
  EXPECT_TRUE(capability_verdict_agrees(false, CapabilityVerdict::refused));
  EXPECT_FALSE(capability_verdict_agrees(false, CapabilityVerdict::holds));  // a disagreement
  EXPECT_FALSE(capability_verdict_agrees(false, CapabilityVerdict::neither));
}

CapabilityRun run(const std::string& method, const std::string& variant, std::optional<double> energy,
                  std::optional<double> relmse, json knobs = json::object()) {
  CapabilityRun out;
  out.method = method;
  out.variant = variant;
  out.label = method + " @" + variant;
  knobs["variant"] = variant;
  out.knobs = knobs;
  out.energy_ratio = energy;
  out.relmse = relmse;
  return out;
}

TEST(CapabilityMatrixReport, BuiltFromSyntheticRecords) {
  const json settings = json::parse(R"({
    "published": {"title": "Table 1", "rows": {"point_light": ["Local point illumination"]},
                  "methods": {"photon_map": ["point_light"], "pinhole": [], "csl": ["point_light"]}},
    "select": {"pinhole": "interaction=reflect"},
    "cases": [
      {"capability": "point_light", "with": "near", "without": "far", "built_on": "reflection", "select": {}},
      {"capability": "multiple_bounces", "with": "two", "without": "one", "built_on": "", "select": {}}],
    "declared": {
      "photon_map": {"capabilities": {"reflection": true, "point_light": true, "multiple_bounces": true}, "notes": {}},
      "pinhole": {"capabilities": {"reflection": true, "point_light": false, "multiple_bounces": false},
                  "notes": {"point_light": "taken as distant"}},
      "csl": {"capabilities": {"reflection": false, "point_light": true, "multiple_bounces": false}, "notes": {}}}})");
  std::vector<CapabilityRun> runs = {
      run("photon_map", "near", 1.02, 0.05), run("photon_map", "far", 1.0, 0.01),
      run("photon_map", "two", 0.5, 0.6),  // declared true, measured wrong: the disagreement
      run("photon_map", "one", 0.98, 0.02),
      run("pinhole", "near", 3.4, 460.0, {{"interaction", "reflect"}}),
      run("pinhole", "near", 1.0, 0.0, {{"interaction", "refract"}}),  // not the selected run
      run("pinhole", "far", 1.01, 0.02, {{"interaction", "reflect"}}),
      run("pinhole", "two", 0.0, 0.04, {{"interaction", "reflect"}}),
      run("csl", "near", 0.1, 30.0),  // built on reflection, which csl declares false: not judged
      run("csl", "far", 0.1, 30.0)};
  CapabilityRun refused = run("pinhole", "one", std::nullopt, std::nullopt, {{"interaction", "reflect"}});
  refused.failed = true;
  refused.error = "pinhole declines the scene";
  runs.push_back(refused);

  const CapabilityMatrix matrix = build_capability_matrix(settings, runs, {{"near", 0.001}, {"two", 0.5}});
  ASSERT_EQ(matrix.rows.size(), 2u);
  EXPECT_EQ(matrix.methods, (std::vector<std::string>{"csl", "photon_map", "pinhole"}));
  const CapabilityRow& point = matrix.rows[0];
  EXPECT_EQ(point.table_rows, std::vector<std::string>{"Local point illumination"});
  const CapabilityCell& csl = point.cells[0];
  const CapabilityCell& photon_map = point.cells[1];
  const CapabilityCell& pinhole = point.cells[2];
  EXPECT_EQ(photon_map.with.verdict, CapabilityVerdict::holds);
  EXPECT_TRUE(photon_map.flags.empty());
  EXPECT_EQ(pinhole.with.verdict, CapabilityVerdict::wrong);
  EXPECT_EQ(*pinhole.with.energy_ratio, 3.4);  // the interaction=reflect run, as selected
  EXPECT_EQ(*pinhole.without.energy_ratio, 1.01);
  EXPECT_EQ(pinhole.published, std::optional<bool>(false));
  EXPECT_TRUE(pinhole.flags.empty()) << pinhole.flags.front();
  EXPECT_FALSE(csl.judged);
  EXPECT_TRUE(csl.flags.empty());

  const CapabilityRow& bounces = matrix.rows[1];
  EXPECT_FALSE(bounces.cells[1].published.has_value());  // the table has no row
  ASSERT_EQ(bounces.cells[1].flags.size(), 1u);
  EXPECT_NE(bounces.cells[1].flags[0].find("declared true, measured wrong"), std::string::npos) << bounces.cells[1].flags[0];
  EXPECT_EQ(bounces.cells[2].with.verdict, CapabilityVerdict::wrong);
  EXPECT_EQ(bounces.cells[2].without.verdict, CapabilityVerdict::refused);
  EXPECT_EQ(bounces.cells[2].without.error, "pinhole declines the scene");
  ASSERT_EQ(matrix.notes.size(), 1u);  // the noisy reference of "two"

  const std::string markdown = capability_matrix_markdown(matrix);
  EXPECT_NE(markdown.find("## Capability matrix"), std::string::npos);
  EXPECT_NE(markdown.find("(!1) photon_map multiple_bounces: declared true, measured wrong"), std::string::npos) << markdown;
  EXPECT_EQ(markdown.find("(!2)"), std::string::npos) << markdown;
  const json out = capability_matrix_json(matrix);
  EXPECT_EQ(out["rows"][0]["methods"]["pinhole"]["with"]["verdict"], "wrong");
  EXPECT_EQ(out["rows"][1]["methods"]["photon_map"]["flags"].size(), 1u);
  EXPECT_NE(capability_matrix_html(matrix).find("class=\"warn\""), std::string::npos);

  // A paper that marks what the code denies is a disagreement without any measurement.
  json paper_disagrees = settings;
  paper_disagrees["published"]["methods"]["pinhole"] = {"point_light"};
  const CapabilityMatrix second = build_capability_matrix(paper_disagrees, runs, {});
  ASSERT_EQ(second.rows[0].cells[2].flags.size(), 2u);
  EXPECT_NE(second.rows[0].cells[2].flags[0].find("Table 1 marks it, the code declares false (taken as distant)"),
            std::string::npos);
  EXPECT_NE(second.rows[0].cells[2].flags[1].find("Table 1 marks it, measured wrong"), std::string::npos);
}

const std::string kStudy = std::string(CAUSTICBENCH_SCENES) + "/../experiments/study_capabilities.yaml";

std::string study_text() {
  std::ifstream in(kStudy);
  std::stringstream text;
  text << in.rdbuf();
  // Scene paths made absolute, so that a copy elsewhere reads the same scenes.
  return std::regex_replace(text.str(), std::regex("\\.\\./scenes/"), std::string(CAUSTICBENCH_SCENES) + "/");
}

TEST(CapabilityMatrixExperiment, ValidatesAndStoresTheDeclarations) {
  const Experiment experiment = load_experiment(kStudy);
  const json& matrix = experiment.report.capability_matrix;
  ASSERT_TRUE(matrix.is_object());
  EXPECT_EQ(matrix["cases"].size(), Capabilities{}.entries().size());
  // Liu's columns, all of which the suite implements: photon map, caustic mapping, caustic volume,
  // pinhole, PRT, LPI, CSL; each one a method.
  EXPECT_EQ(matrix["published"]["methods"].size(), 7u);
  for (const auto& [method, marks] : matrix["published"]["methods"].items()) EXPECT_NO_THROW(find_method(method)) << method;
  // Judged at frame 1 with frame 0 played first, so that the moving cases move (tests/test_capabilities.cpp).
  EXPECT_EQ(matrix["frame"], 1);
  EXPECT_EQ(experiment.frames, (std::vector<int>{0, 1}));
  for (const std::string& method : native_method_names()) {
    ASSERT_TRUE(matrix["declared"].contains(method)) << method;
    for (const auto& [name, value] : find_method(method).info().capabilities.entries())
      EXPECT_EQ(matrix["declared"][method]["capabilities"][name], value) << method << " " << name;
  }
  EXPECT_EQ(experiment.to_json()["capability_matrix"], matrix);  // what experiment.json stores
  EXPECT_FALSE(load_experiment(std::string(CAUSTICBENCH_SCENES) + "/../experiments/quickstart.yaml").to_json().contains(
      "capability_matrix"));
}

// Each defect is refused with the file, line and key, like every other key.
TEST(CapabilityMatrixExperiment, RefusesDefectsWithFileLineAndKey) {
  testing::TemporaryFolder folder("capability_matrix_experiment");
  const std::string text = study_text();
  ASSERT_NO_THROW(load_experiment(folder.write("good.yaml", text)));
  const std::vector<std::tuple<std::string, std::string, std::string>> defects = {
      {"{capability: point_light, with:", "{capability: point_lite, with:", "did you mean 'point_light'"},
      {"without: occlusion_without,", "without: occlusion_with,", "a variant of the experiment"},
      {"  select: {pinhole: interaction=reflect, lpi: light_subdivision=0, prt: volume_radius=7}\n", "", "one run of"},
      {"lpi: [directional_light,", "lpi: [reflection, directional_light,", "a capability that `rows` maps"},
      {"      occlusion: [Occluded caustic light]\n", "      occlusion: [Occluded caustic light]\n      colour: [x]\n",
       "capability_matrix.published.rows.colour"},
      {"  select: {pinhole: interaction=reflect,", "  select: {pinhole: interaction=reflekt,", "interaction"},
      {"metrics: [relmse, energy_ratio]", "metrics: [relmse]", "energy_ratio"},
      {"  frame: 1\n", "  frame: 2\n", "one of the experiment's frames (0, 1)"},
  };
  for (const auto& [from, to, expected] : defects) {
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    std::string broken = text;
    broken.replace(at, from.size(), to);
    const std::string path = folder.write("broken.yaml", broken);
    try {
      load_experiment(path);
      ADD_FAILURE() << "accepted: " << to;
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(path + ":"), std::string::npos) << message;  // file:line:column
      EXPECT_NE(message.find(expected), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace causticbench
