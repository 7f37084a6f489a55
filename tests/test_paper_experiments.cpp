// The papers' experiments (configs/experiments/wyman2003_*.yaml, issue 11 item 6): each validates, its
// per-object method entries run only on their objects, and the first run of every method entry (its
// cheapest: the sweeps are written cheapest first) on that entry's first variant runs end to end at a
// tiny size. The tiny copy differs from the shipped file only in its one-line overrides, reference,
// repetitions and frames, and in photon counts (lpi's photons_per_sample and photon_map's photons
// become 5,000): its scenes, variants, storages and light-sample sets are the shipped ones.
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "experiments/experiment.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string tiny_copy(const std::string& text) {
  std::string tiny = testing::tiny_experiment(text, 20);
  tiny = std::regex_replace(tiny, std::regex("\nframes: [^\n]*"), "\nframes: {first: 0, count: 2}");
  tiny = std::regex_replace(tiny, std::regex("photons_per_sample: [0-9]+"), "photons_per_sample: 5000");
  return std::regex_replace(tiny, std::regex("photons: [0-9]+"), "photons: 5000");
}

// A run's label without its swept knobs (" knob=value") and variant (" @name"): its method entry's label.
std::string entry_label(const std::string& label) {
  std::string entry, word;
  std::istringstream words(label);
  while (words >> word)
    if (word.find('=') == std::string::npos && word.front() != '@') entry += (entry.empty() ? "" : " ") + word;
  return entry;
}

// Every knob of the run, so that the filter selects it alone among entries that fix different knobs.
std::string filter_of(const RunSpec& run, const std::string& variant) {
  std::string filter = "method=" + run.method + ",variant=" + variant;
  for (const auto& [knob, value] : run.params.values()) filter += "," + knob + "=" + format_param_value(value);
  return filter;
}

TEST(PaperExperiments, PerObjectEntriesRunOnlyOnTheirObjects) {
  const Experiment experiment = load_experiment(std::string(CAUSTICBENCH_SCENES) + "/../experiments/wyman2003_light_samples.yaml");
  std::map<std::string, std::set<std::string>> variants_of_label;
  for (const RunSpec& run : experiment.runs) {
    variants_of_label[entry_label(run.label)].insert(experiment.variants[run.variant].name);
  }
  EXPECT_EQ(variants_of_label["lpi sphere symmetric"], (std::set<std::string>{"sphere"}));
  EXPECT_EQ(variants_of_label["lpi ring faces"], (std::set<std::string>{"ring"}));
  EXPECT_EQ(variants_of_label["lpi flat faces"], (std::set<std::string>{"cube", "prism"}));
  // 3 (one light sample in each precision) + 3 sphere, 3 + 2 ring, 4 cube and 4 prism.
  EXPECT_EQ(experiment.runs.size(), 19u);
}

TEST(PaperExperiments, CheapestSettingOfEveryEntryRunsEndToEnd) {
  const std::vector<fs::path> files = testing::shipped_experiments("wyman2003_");
  ASSERT_GE(files.size(), 6u) << "Table 1, Figs. 9 and 11, light samples, animated light, triangle count";
  testing::TemporaryFolder folder("paper_experiments_end_to_end");
  // The copies sit in experiments/ beside a link to the shipped scenes/, so that the variants' relative
  // scene paths resolve as they do in configs/.
  fs::create_directories(folder.path("experiments"));
  fs::create_directory_symlink(CAUSTICBENCH_SCENES, folder.path("scenes"));
  const std::string results = folder.path("results");
  for (const fs::path& file : files) {
    const std::string tiny = folder.write("experiments/" + file.filename().string(), tiny_copy(testing::read_whole_file(file)));
    const Experiment experiment = load_experiment(tiny);
    // The first run of each method entry: its first combination on its first variant.
    std::set<std::string> seen;
    for (const RunSpec& run : experiment.runs) {
      if (!seen.insert(entry_label(run.label)).second) continue;
      const std::string filter = filter_of(run, experiment.variants[run.variant].name);
      std::string output;
      const int code = testing::run_command(std::string(CAUSTICBENCH_BINARY) + " -q run " + tiny + " --results " + results +
                                                " --no-report --filter '" + filter + "'",
                                            output);
      ASSERT_EQ(code, 0) << file << " " << filter << "\n" << output;
      EXPECT_NE(output.find("1 selected"), std::string::npos) << filter << "\n" << output;
      const fs::path record_path = fs::path(results) / experiment.name / "runs" / run.key / "record.json";
      ASSERT_TRUE(fs::is_regular_file(record_path)) << record_path;
      const json record = json::parse(testing::read_whole_file(record_path));
      ASSERT_EQ(record.at("status"), "ok") << record_path << ": " << record.value("error", "");
      EXPECT_TRUE(record.at("metrics").contains(experiment.primary_metric)) << record_path;
      EXPECT_EQ(record.at("metrics").value("nonfinite_pixels", 0.0), 0.0) << record_path;
      if (run.method == "lpi") {
        EXPECT_GT(record.at("counters").at("light_samples").get<double>(), 0.0) << record_path;
      }
    }
  }
}

}  // namespace
}  // namespace causticbench
