// Issue 50, items 11 and 12: every text a user supplies (a run's label, an experiment's description, a
// claim's text) reaches every output escaped. A label with "<!--" once blanked viewer.html (its embedded
// JSON escaped only "</"), and report.md wrote labels and claims as raw HTML that a Markdown renderer
// keeping HTML would run. A real sweep with hostile text, then each document read back.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const char* const kHostile = "<img src=x onerror=alert(1)> <!-- <script>alert(2)</script> & `tick`";

TEST(HostileText, LabelsDescriptionsAndClaimsAreEscapedInEveryDocument) {
  testing::TemporaryFolder folder("hostile_text");
  folder.write("scene.yaml", testing::replace_once(testing::kSmallGlassSphere, "resolution: [40, 40]", "resolution: [24, 24]"));
  const std::string file = folder.write("hostile.yaml", std::string(R"(name: hostile
description: "A description )") + kHostile + R"("
scene: scene.yaml
reference: {photons_per_pass: 100000, max_passes: 2, target_error: 0}
repetitions: 1
methods:
  - method: photon_map
    label: ")" + kHostile + R"("
    sweep: {photons: [20000, 40000]}
claims:
  - text: ")" + kHostile + R"("
    kind: better
    metric: relmse
    run: photons=40000
    than: photons=20000
)");
  std::string output;
  ASSERT_EQ(testing::run_command(std::string(CAUSTICBENCH_BINARY) + " -q run " + file + " --results " + folder.path("results"), output), 0)
      << output;
  const fs::path report = fs::path(folder.path("results")) / "hostile";

  // Markdown: no tag of the user's survives as a tag; the text is there, as entities.
  const std::string markdown = testing::read_whole_file(report / "report.md");
  for (const std::string tag : {"<img", "<script", "<!--", "</script"})
    EXPECT_EQ(markdown.find(tag), std::string::npos) << "report.md holds " << tag << ":\n" << markdown;
  EXPECT_NE(markdown.find("&lt;img src=x onerror=alert(1)&gt;"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("A description &lt;img"), std::string::npos) << "the description, escaped";

  // HTML: the same; the user's text only as text.
  const std::string html = testing::read_whole_file(report / "report.html");
  for (const std::string tag : {"<img src=x", "<script>alert", "<!-- <script"})
    EXPECT_EQ(html.find(tag), std::string::npos) << "report.html holds " << tag;

  // The viewer: its embedded index holds no "<" at all, so "<!--" cannot open a comment and blank the
  // page; parsed back, it names the experiment and both runs with their labels whole.
  const std::string viewer = testing::read_whole_file(report / "viewer.html");
  for (const std::string tag : {"<img src=x", "<!-- <script", "<script>alert"})
    EXPECT_EQ(viewer.find(tag), std::string::npos) << "viewer.html holds " << tag;
  const size_t start = viewer.find("const INDEX = ") + 14;
  ASSERT_NE(start, std::string::npos + 14);
  size_t depth = 0, end = start;
  bool in_string = false;
  for (; end < viewer.size(); ++end) {
    const char c = viewer[end];
    if (in_string) {
      if (c == '\\') ++end;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '{') {
      ++depth;
    } else if (c == '}' && --depth == 0) {
      break;
    }
  }
  const json index = json::parse(viewer.substr(start, end - start + 1));
  EXPECT_EQ(index.value("experiment", ""), "hostile");
  EXPECT_NE(index.dump().find(kHostile), std::string::npos) << "the label reaches the viewer whole";
}

}  // namespace
}  // namespace causticbench
