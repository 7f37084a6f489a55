// Plugins (methods/plugin.h, methods/plugins.h, docs/sdk.md): the example method of examples/, loaded with
// --plugin, an experiment's plugins: list and CAUSTICBENCH_PLUGINS, is listed, described, rendered and
// run next to photon_map, its identity in its run keys (a rebuilt plugin is measured again); a library of
// another SDK version, one without the entry point, one whose registration throws, one whose method takes
// a built-in name, a missing file and a file that is no library are each refused with exit code 2 and a
// message naming it, nothing stored; and the example built out of the tree against an installed SDK.
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/report_test_support.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using report_testing::read_text;

std::string plugin(const std::string& name) { return std::string(CAUSTICBENCH_TEST_PLUGINS) + "/test_plugin_" + name + ".so"; }

std::string causticbench(const std::string& arguments) { return std::string(CAUSTICBENCH_BINARY) + " " + arguments; }

class Plugins : public ::testing::Test {
 protected:
  void SetUp() override {
    folder.write("scene.yaml", testing::replace_once(testing::kSmallGlassSphere, "resolution: [40, 40]", "resolution: [24, 24]"));
  }
  // An experiment with photon_map and the example plugin's method, the plugin named by `plugins`.
  std::string experiment(const std::string& name, const std::string& plugins) const {
    return folder.write(name + ".yaml", "name: " + name + R"(
scene: scene.yaml
reference: {photons_per_pass: 100000, max_passes: 2, target_error: 0}
repetitions: 1
)" + plugins + R"(methods:
  - method: photon_map
  - method: fixed_radius_splat
    frame: {photons: 20000}
    sweep: {radius: [0.05, 0.1]}
)");
  }
  std::vector<json> records(const std::string& name) const {
    std::vector<json> found;
    const fs::path runs = folder.path("results") + "/" + name + "/runs";
    if (!fs::exists(runs)) return found;
    for (const auto& entry : fs::directory_iterator(runs)) found.push_back(json::parse(read_text(entry.path() / "record.json")));
    return found;
  }
  // One folder per test: CTest runs the tests of this fixture as processes side by side.
  testing::TemporaryFolder folder{std::string("plugins_") + ::testing::UnitTest::GetInstance()->current_test_info()->name()};
};

TEST_F(Plugins, TheExampleIsListedDescribedRenderedAndRunBesideTheBuiltInMethods) {
  std::string output;
  ASSERT_EQ(testing::run_command(causticbench("--plugin " + plugin("example") + " list"), output), 0) << output;
  EXPECT_NE(output.find("fixed_radius_splat Traces caustic photons"), std::string::npos) << output;
  EXPECT_NE(output.find("[plugin fixed_radius_splat 1.0, "), std::string::npos) << output;
  // After the subcommand too; and without the plugin the method is unknown.
  ASSERT_EQ(testing::run_command(causticbench("describe fixed_radius_splat --plugin " + plugin("example")), output), 0) << output;
  EXPECT_NE(output.find("radius"), std::string::npos);
  EXPECT_NE(output.find("From plugin fixed_radius_splat 1.0"), std::string::npos) << output;
  EXPECT_EQ(testing::run_command(causticbench("describe fixed_radius_splat"), output), 2) << output;
  ASSERT_EQ(testing::run_command(causticbench("render " + folder.path("scene.yaml") + " --method fixed_radius_splat --set photons=20000 --out " +
                                              folder.path("render") + " --plugin " + plugin("example")),
                                 output),
            0)
      << output;
  EXPECT_TRUE(fs::is_regular_file(folder.path("render") + "/caustic.exr"));

  // An experiment's plugins: list, relative to the file.
  fs::copy_file(plugin("example"), folder.path("splat.so"));
  const std::string file = experiment("beside", "plugins: [splat.so]\n");
  ASSERT_EQ(testing::run_command(causticbench("run " + file + " --results " + folder.path("results")), output), 0) << output;
  EXPECT_NE(output.find("3 run now, 0 failed"), std::string::npos) << output;
  std::string hash;
  for (const json& record : records("beside")) {
    EXPECT_EQ(record["status"], "ok") << record["error"];
    if (record["method"] != "fixed_radius_splat") continue;
    EXPECT_GT(record["metrics"]["relmse"].get<double>(), 0.0);
    EXPECT_EQ(record["spec"]["plugin"]["name"], "fixed_radius_splat");
    hash = record["spec"]["plugin"]["hash"];
  }
  EXPECT_EQ(hash.size(), 16u);
  const json experiment_json = json::parse(read_text(folder.path("results") + "/beside/experiment.json"));
  EXPECT_EQ(experiment_json["plugins"][0]["hash"], hash);
  const std::string markdown = read_text(folder.path("results") + "/beside/report.md");
  EXPECT_NE(markdown.find("fixed_radius_splat 1.0 (xxhash " + hash), std::string::npos) << "the report names the build";

  // Stored: nothing to do. A rebuilt plugin (other bytes) has other keys: its runs are measured again,
  // photon_map's are not. Loaded through CAUSTICBENCH_PLUGINS this time.
  ASSERT_EQ(testing::run_command(causticbench("run " + file + " --results " + folder.path("results") + " --no-report"), output), 0);
  EXPECT_NE(output.find("0 run now"), std::string::npos) << output;
  {
    std::ofstream rebuilt(folder.path("splat.so"), std::ios::app | std::ios::binary);
    rebuilt << "a rebuilt plugin";
  }
  const std::string by_environment = experiment("beside", "");
  ASSERT_EQ(testing::run_command("CAUSTICBENCH_PLUGINS=" + folder.path("splat.so") + " " +
                                     causticbench("run " + by_environment + " --results " + folder.path("results") + " --no-report"),
                                 output),
            0)
      << output;
  EXPECT_NE(output.find("2 run now, 0 failed"), std::string::npos) << output;
}

// A plugin's stored build is keyed with the plugin's identity: a second experiment loads it, a rebuilt
// plugin (other bytes) computes its own.
TEST_F(Plugins, APluginsBuildIsCachedAndARebuiltPluginComputesItsOwn) {
  fs::copy_file(plugin("cached"), folder.path("cached.so"));
  auto run_cached = [&](const std::string& name, const std::string& library) {
    const std::string file = folder.write(name + ".yaml", "name: " + name + R"(
scene: scene.yaml
reference: {photons_per_pass: 100000, max_passes: 2, target_error: 0}
repetitions: 1
plugins: [)" + library + R"(]
methods:
  - method: cached_constant
)");
    std::string output;
    EXPECT_EQ(testing::run_command(causticbench("run " + file + " --results " + folder.path("results") + " --no-report"), output), 0)
        << output;
    const std::vector<json> found = records(name);
    return found.size() == 1 ? found.front() : json();
  };
  const json first = run_cached("first", "cached.so");
  ASSERT_TRUE(first.is_object());
  EXPECT_EQ(first["prepare"]["source"], "computed");
  EXPECT_EQ(first["method_record"]["level"], 3.0) << "two objects and the offset";
  const json second = run_cached("second", "cached.so");
  EXPECT_EQ(second["prepare"]["source"], "loaded");
  EXPECT_EQ(second["prepare"]["build_key"], first["prepare"]["build_key"]);
  EXPECT_EQ(second["method_record"]["level"], 3.0);
  fs::copy_file(plugin("cached"), folder.path("rebuilt.so"));
  std::ofstream(folder.path("rebuilt.so"), std::ios::app | std::ios::binary) << "rebuilt";
  const json third = run_cached("third", "rebuilt.so");
  EXPECT_EQ(third["prepare"]["source"], "computed");
  EXPECT_NE(third["prepare"]["build_key"], first["prepare"]["build_key"]);
}

TEST_F(Plugins, BadPluginsAreRefusedWithExitTwoAndNothingStored) {
  fs::copy_file(plugin("example"), folder.path("splat.so"));
  folder.write("text.so", "not a shared library\n");
  // Cut in half: dlopen() would map its segments past the end of the file and die of SIGBUS (issue 50, 4).
  fs::copy_file(plugin("example"), folder.path("truncated.so"));
  fs::resize_file(folder.path("truncated.so"), fs::file_size(plugin("example")) / 2);
  fs::create_directory(folder.path("folder.so"));
  const struct {
    std::string path, message;
  } cases[] = {
      {plugin("abi_mismatch"), "built against causticbench SDK version 1001, but this causticbench is SDK version 3"},
      {plugin("no_entry_point"), "exports no causticbench_plugin(): not a causticbench plugin"},
      {plugin("throwing"), "plugin throwing (" + plugin("throwing") + "): its registration failed: the licence file licence.txt is missing"},
      {plugin("clash"), "its method 'photon_map' clashes with the built-in method of that name"},
      {folder.path("missing.so"), "plugin " + folder.path("missing.so") + ": no such file"},
      {folder.path("text.so"), ": cannot be loaded: it is not an ELF shared library"},
      {folder.path("truncated.so"), ": the file is truncated"},
      {folder.path("folder.so"), "plugin " + folder.path("folder.so") + ": it is a folder, not a file"},
      {plugin("info_throws"), "a method's info() failed: it threw a value of type int, which is not a std::exception"},
  };
  for (const auto& bad : cases) {
    SCOPED_TRACE(bad.path);
    std::string output;
    EXPECT_EQ(testing::run_command(causticbench("--plugin " + bad.path + " list"), output), 2) << output;
    EXPECT_NE(output.find(bad.message), std::string::npos) << output;
    // In an experiment's plugins: list beside a good one: refused before any work, with the file and line.
    const std::string file = experiment("refused", "plugins: [splat.so, " + bad.path + "]\n");
    EXPECT_EQ(testing::run_command(causticbench("run " + file + " --results " + folder.path("results")), output), 2) << output;
    EXPECT_NE(output.find("refused.yaml:5"), std::string::npos) << output;
    EXPECT_NE(output.find(bad.message), std::string::npos) << output;
    EXPECT_TRUE(records("refused").empty());
    EXPECT_FALSE(fs::exists(folder.path("results") + "/references")) << "no reference computed";
    // Through the environment, for a command that loads no plugin of its own.
    EXPECT_EQ(testing::run_command("CAUSTICBENCH_PLUGINS=" + bad.path + " " + causticbench("validate " + file), output), 2) << output;
    EXPECT_NE(output.find(bad.message), std::string::npos) << output;
  }
}

// Issue 50, items 1 and 2: a method whose render() returns an image smaller than the G-buffer, one that
// throws an int, and one whose constructor throws a std::string each fail their runs alone, with a
// message; photon_map after them runs; `render` exits with 1 and says why; `conform` prints FAIL for the
// size check instead of crashing.
TEST_F(Plugins, AMethodThatBreaksTheInterfaceFailsItsRunAlone) {
  const std::string file = folder.write("hostile.yaml", R"(name: hostile
scene: scene.yaml
reference: {photons_per_pass: 100000, max_passes: 2, target_error: 0}
repetitions: 1
plugins: [)" + plugin("hostile") + R"(]
methods:
  - method: shrunken
  - method: int_thrower
  - method: constructor_thrower
  - method: photon_map
    build: {photons: 20000}
)");
  std::string output;
  ASSERT_EQ(testing::run_command(causticbench("run " + file + " --results " + folder.path("results") + " --no-report"), output), 0)
      << output;
  EXPECT_NE(output.find("1 run now, 3 failed"), std::string::npos) << output;
  const std::map<std::string, std::string> expected = {
      {"shrunken", "shrunken's render() returned a 12x12 image with 3 channels; expected 24x24 with 3 (RGB)"},
      {"int_thrower", "update() or render() of method int_thrower: it threw a value of type int, which is not a std::exception"},
      {"constructor_thrower", "constructing method constructor_thrower: it threw a value of type std::"},
  };
  size_t seen = 0;
  for (const json& record : records("hostile")) {
    const std::string method = record["method"];
    if (method == "photon_map") {
      EXPECT_EQ(record["status"], "ok") << record.dump();
      continue;
    }
    ++seen;
    EXPECT_EQ(record["status"], "failed") << method;
    EXPECT_NE(record.value("error", "").find(expected.at(method)), std::string::npos) << record.value("error", "");
  }
  EXPECT_EQ(seen, 3u);
  for (const auto& [method, message] : expected) {
    EXPECT_EQ(testing::run_command(causticbench("render " + folder.path("scene.yaml") + " --method " + method + " --out " +
                                                folder.path("render_" + method) + " --plugin " + plugin("hostile")),
                                   output),
              1)
        << output;
    EXPECT_NE(output.find("error: "), std::string::npos) << output;
    EXPECT_NE(output.find(message), std::string::npos) << output;
  }
  EXPECT_EQ(testing::run_command(causticbench("conform --plugin " + plugin("hostile") + " shrunken"), output), 1) << output;
  EXPECT_NE(output.find("FAIL     Registry/Conformance.OutputIsWellFormedOnEveryShippedSceneItAccepts/shrunken"),
            std::string::npos)
      << output;
}

// `conform`: the suites every built-in method passes, on a plugin's methods. The example passes them; a
// method that lights the receivers with a constant and declares reflection fails its capability checks,
// and the command says which, with exit code 1.
TEST_F(Plugins, ConformRunsTheBuiltInMethodsChecksOnAPlugin) {
  std::string output;
  ASSERT_EQ(testing::run_command(causticbench("conform --plugin " + plugin("example")), output), 0) << output;
  EXPECT_NE(output.find("pass     Registry/Conformance.OutputIsWellFormedOnEveryShippedSceneItAccepts/fixed_radius_splat"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("pass     AllMethods/CapabilityConformance.DeclarationMatchesMeasurement/fixed_radius_splat_refraction"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find(" 0 failed"), std::string::npos) << output;
  EXPECT_EQ(testing::run_command(causticbench("conform --plugin " + plugin("nonconforming") + " floodlight"), output), 1) << output;
  EXPECT_NE(output.find("FAIL     AllMethods/CapabilityConformance.DeclarationMatchesMeasurement/floodlight_reflection"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("declared capability does not hold: method floodlight capability reflection"), std::string::npos)
      << output;
  EXPECT_EQ(testing::run_command(causticbench("conform"), output), 2) << output;
  EXPECT_NE(output.find("load a plugin with --plugin PATH"), std::string::npos) << output;
}

// The example built out of the tree: causticbench installed into a temporary prefix, the example
// configured against it with find_package(causticbench), built, and run by the installed executable next
// to photon_map.
TEST_F(Plugins, TheExampleBuildsOutOfTreeAgainstTheInstalledSdk) {
  std::string output;
  const std::string prefix = folder.path("prefix"), build = folder.path("example-build");
  ASSERT_EQ(testing::run_command("cmake --install " + std::string(CAUSTICBENCH_BUILD_DIR) + " --prefix " + prefix, output), 0)
      << output;
  EXPECT_TRUE(fs::is_regular_file(prefix + "/include/causticbench/methods/plugin.h"));
  EXPECT_FALSE(fs::exists(prefix + "/include/causticbench/experiments")) << "only the SDK's surface is installed";
  ASSERT_EQ(testing::run_command("cmake -S " + std::string(CAUSTICBENCH_EXAMPLE_DIR) + " -B " + build +
                                     " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" + prefix + " && cmake --build " + build,
                                 output),
            0)
      << output;
  const std::string library = build + "/fixed_radius_splat.so";
  ASSERT_TRUE(fs::is_regular_file(library)) << output;
  const std::string file = experiment("out_of_tree", "plugins: [" + library + "]\n");
  ASSERT_EQ(testing::run_command(prefix + "/bin/causticbench run " + file + " --results " + folder.path("results") + " --no-report", output), 0)
      << output;
  EXPECT_NE(output.find("3 run now, 0 failed"), std::string::npos) << output;
  // The installed conform runs the installed suites on it.
  ASSERT_EQ(testing::run_command(prefix + "/bin/causticbench conform --plugin " + library, output), 0) << output;
  EXPECT_NE(output.find(prefix + "/bin/causticbench-conformance"), std::string::npos) << output;
}

}  // namespace
}  // namespace causticbench
