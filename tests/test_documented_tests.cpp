// Every test a document names exists, so that a number quoted beside a test's name keeps a test behind it
// (issue 51: a renamed or deleted test would otherwise leave its README's "Measured" row standing on
// nothing). The names are read from the Markdown documents (README.md, docs/, every method's README.md)
// and, for names of a known suite, from the sources, experiments and scripts:
//   - `Suite.Name` (a GoogleTest name; DISABLED_ included) is a test of some executable in build/tests/;
//   - build/tests/<executable> [...] --gtest_filter='...' : the executable exists and the filter selects
//     at least one of its tests; a filter that selects only disabled tests needs
//     --gtest_also_run_disabled_tests on the same line (or the command runs nothing);
//   - <executable> --gtest_filter without its path is refused: a reader copies the command as written;
//   - methods/<m>/tests/test_x.cpp and tests/test_x.cpp are paths from the repository's root.
// Test names are read from the test sources' TEST, TEST_F and TEST_P lines; what a filter selects is asked
// of the executable itself (--gtest_list_tests), so that it counts as GoogleTest counts.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;

const fs::path kRoot = CAUSTICBENCH_SOURCE_DIR;

// build/tests/, where every test executable is written (cmake/tests.cmake).
fs::path test_folder() { return fs::path(CAUSTICBENCH_BINARY).parent_path().parent_path() / "tests"; }

// "Suite.Name" of every test `executable` lists under `filter` ("" for all), parameterised tests by the
// names they were declared with (an instantiation's "Prefix/" and a parameter's "/0" dropped).
std::vector<std::string> listed_tests(const fs::path& executable, const std::string& filter) {
  std::string command = "'" + executable.string() + "' --gtest_list_tests";
  if (!filter.empty()) command += " '--gtest_filter=" + filter + "'";
  std::string output;
  if (testing::run_command(command + " 2>/dev/null", output) != 0) return {};
  std::vector<std::string> tests;
  std::istringstream lines(output);
  std::string line, suite;
  while (std::getline(lines, line)) {
    const std::string text = line.substr(0, line.find('#'));
    const size_t begin = text.find_first_not_of(' '), end = text.find_last_not_of(' ');
    if (begin == std::string::npos) continue;
    std::string word = text.substr(begin, end - begin + 1);
    if (begin == 0) {
      if (!word.empty() && word.back() == '.') word.pop_back();
      suite = word.substr(word.find('/') == std::string::npos ? 0 : word.find('/') + 1);
    } else {
      tests.push_back(suite + "." + word.substr(0, word.find('/')));
    }
  }
  return tests;
}

// Every test the sources define, "Suite.Name" (TEST, TEST_F and TEST_P), and their suites.
struct Tree {
  std::set<std::string> tests, suites;
};

std::string read(const fs::path& path);

const Tree& tree() {
  static const Tree built = [] {
    Tree tree;
    const std::regex definition("\\bTEST(?:_F|_P)?\\(\\s*(\\w+)\\s*,\\s*(\\w+)\\s*\\)");
    for (const char* folder : {"tests", "methods"}) {
      for (const fs::directory_entry& entry : fs::recursive_directory_iterator(kRoot / folder)) {
        if (entry.path().extension() != ".cpp") continue;
        const std::string text = read(entry.path());
        for (std::sregex_iterator match(text.begin(), text.end(), definition), end; match != end; ++match) {
          tree.tests.insert((*match)[1].str() + "." + (*match)[2].str());
          tree.suites.insert((*match)[1].str());
        }
      }
    }
    return tree;
  }();
  return built;
}

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Where in `text` offset `at` lies: "file:line".
std::string where(const fs::path& file, const std::string& text, size_t at) {
  return fs::relative(file, kRoot).string() + ":" + std::to_string(1 + std::count(text.begin(), text.begin() + at, '\n'));
}

std::vector<fs::path> documents() {
  std::vector<fs::path> files = {kRoot / "README.md"};
  for (const fs::path& folder : {kRoot / "docs", kRoot / "methods"}) {
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(folder)) {
      if (entry.path().extension() == ".md") files.push_back(entry.path());
    }
  }
  return files;
}

std::vector<fs::path> sources() {
  std::vector<fs::path> files;
  for (const char* folder : {"apps", "core", "experiments", "gpu", "methods", "metrics", "reports", "store", "tests",
                             "configs", "scripts"}) {
    if (!fs::exists(kRoot / folder)) continue;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(kRoot / folder)) {
      const std::string extension = entry.path().extension().string();
      if (entry.is_regular_file() && (extension == ".h" || extension == ".cpp" || extension == ".yaml" ||
                                      extension == ".py" || extension == ".sh" || extension == ".comp")) {
        files.push_back(entry.path());
      }
    }
  }
  return files;
}

TEST(DocumentedTests, TheTestsAreFound) {
  EXPECT_GT(tree().tests.size(), 400u) << kRoot;
  EXPECT_TRUE(tree().tests.count("DocumentedTests.TheTestsAreFound"));
  EXPECT_TRUE(tree().tests.count("Geodesic.DISABLED_LocateThroughput"));
  EXPECT_TRUE(fs::is_directory(test_folder())) << test_folder();
}

TEST(DocumentedTests, EveryTestADocumentNamesExists) {
  const std::regex test_name("`([A-Z][A-Za-z0-9]+)\\.((?:DISABLED_)?[A-Z][A-Za-z0-9_]+)`");
  size_t names = 0;
  for (const fs::path& file : documents()) {
    const std::string text = read(file);
    for (std::sregex_iterator match(text.begin(), text.end(), test_name), end; match != end; ++match, ++names) {
      const std::string name = (*match)[1].str() + "." + (*match)[2].str();
      EXPECT_TRUE(tree().tests.count(name)) << where(file, text, match->position()) << " names the test " << name
                                            << ", which no test source defines";
    }
  }
  // Sources, experiments and scripts name tests in comments without backticks: a name counts when its
  // suite is one of the tests' suites.
  const std::regex bare_name("\\b([A-Z][A-Za-z0-9]+)\\.((?:DISABLED_)?[A-Z][A-Za-z0-9_]+)\\b");
  for (const fs::path& file : sources()) {
    const std::string text = read(file);
    for (std::sregex_iterator match(text.begin(), text.end(), bare_name), end; match != end; ++match) {
      if (!tree().suites.count((*match)[1].str())) continue;
      ++names;
      const std::string name = (*match)[1].str() + "." + (*match)[2].str();
      EXPECT_TRUE(tree().tests.count(name)) << where(file, text, match->position()) << " names the test " << name
                                            << ", which no test source defines";
    }
  }
  EXPECT_GT(names, 20u) << "the documents' test names were not found";
}

TEST(DocumentedTests, EveryTestCommandADocumentGivesRunsATest) {
  // An executable's name, what precedes it on its line (its path) and the rest of the line: a command
  // ends at a backtick or the line's end.
  const std::regex command("([^\\s`'\"]*)\\b(test_[a-z0-9_]+)\\b([^`\\n]*)");
  const std::regex filter("--gtest_filter='?([^'\\s]+)'?");
  size_t commands = 0;
  std::map<std::string, std::vector<std::string>> selections;  // "executable filter": what it selects
  for (const fs::path& file : documents()) {
    const std::string text = read(file);
    for (std::sregex_iterator match(text.begin(), text.end(), command), end; match != end; ++match) {
      const std::string path = (*match)[1].str(), executable = (*match)[2].str(), rest = (*match)[3].str();
      const std::string at = where(file, text, match->position());
      std::smatch chosen;
      const bool filtered = std::regex_search(rest, chosen, filter);
      if (path.size() >= 12 && path.compare(path.size() - 12, 12, "build/tests/") == 0) {
        ++commands;
        ASSERT_TRUE(fs::is_regular_file(test_folder() / executable)) << at << " runs build/tests/" << executable
                                                                     << ", which is not built";
        if (!filtered) continue;
        auto select = [&](const std::string& pattern) -> const std::vector<std::string>& {
          const std::string key = executable + " " + pattern;
          if (!selections.count(key)) selections[key] = listed_tests(test_folder() / executable, pattern);
          return selections[key];
        };
        const std::vector<std::string>& selected = select(chosen[1].str());
        EXPECT_FALSE(selected.empty()) << at << ": " << executable << " --gtest_filter='" << chosen[1].str()
                                       << "' selects no test";
        // Each positive pattern (':' between them, '-' before the negative ones) selects a test of its own:
        // one renamed pattern beside one that still matches would otherwise pass unseen.
        const std::string positive = chosen[1].str().substr(0, chosen[1].str().find('-'));
        for (size_t begin = 0; begin <= positive.size();) {
          const size_t end = std::min(positive.find(':', begin), positive.size());
          const std::string pattern = positive.substr(begin, end - begin);
          if (!pattern.empty() && pattern != positive)
            EXPECT_FALSE(select(pattern).empty()) << at << ": " << executable << " --gtest_filter's pattern '" << pattern
                                                  << "' selects no test";
          begin = end + 1;
        }
        const bool all_disabled = std::all_of(selected.begin(), selected.end(), [](const std::string& test) {
          return test.find(".DISABLED_") != std::string::npos;
        });
        if (!selected.empty() && all_disabled) {
          EXPECT_NE(rest.find("--gtest_also_run_disabled_tests"), std::string::npos)
              << at << ": " << executable << " --gtest_filter='" << chosen[1].str()
              << "' selects only disabled tests; without --gtest_also_run_disabled_tests it runs nothing";
        }
      } else if (filtered && path.empty()) {
        ADD_FAILURE() << at << ": " << executable << " --gtest_filter is given without its path; write build/tests/"
                      << executable << " so that the command runs as written";
      }
    }
  }
  EXPECT_GT(commands, 20u) << "the documents' test commands were not found";
}

// The walkthrough of docs/adding-a-method.md writes a method, splat, that is not in the tree (it was
// built and tested once): its paths are an example, not a reference.
bool example_path(const fs::path& file, const std::string& path) {
  return file.filename() == "adding-a-method.md" &&
         (path.rfind("methods/splat/", 0) == 0 || path == "tests/test_splat.cpp");
}

TEST(DocumentedTests, EveryTestFileADocumentNamesExists) {
  const std::regex test_file("(^|[^\\w/.])((?:methods/[a-z_]+/)?tests/test_[a-z0-9_]+\\.cpp)");
  size_t files = 0;
  for (const fs::path& file : documents()) {
    const std::string text = read(file);
    for (std::sregex_iterator match(text.begin(), text.end(), test_file), end; match != end; ++match) {
      const std::string path = (*match)[2].str();
      if (example_path(file, path)) continue;
      ++files;
      EXPECT_TRUE(fs::exists(kRoot / path)) << where(file, text, match->position()) << " names " << path
                                            << ", which is not a file under the repository's root";
    }
  }
  EXPECT_GT(files, 20u);
}

}  // namespace
}  // namespace causticbench
