// The project's layering, read from the sources: every #include of a project header points down or
// sideways, never back up (docs/design.md, "Layout"), and a method folder includes no other method's
// folder (what two methods share lives in methods/common/). Tests (tests/, methods/<m>/tests/) may
// include anything. Links only the core library; reads the tree at CAUSTICBENCH_SOURCE_DIR.
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace causticbench {
namespace {

namespace fs = std::filesystem;

// Each top-level folder and the folders it may include, itself included. The order is the layering:
// core; gpu (which causticbench-gpubench links alone); metrics; methods; store; experiments; reports; apps.
const std::map<std::string, std::set<std::string>> kMayInclude = {
    {"core", {"core"}},
    {"gpu", {"gpu"}},
    {"metrics", {"metrics", "core"}},
    {"methods", {"methods", "metrics", "gpu", "core"}},
    {"store", {"store", "methods", "metrics", "gpu", "core"}},
    {"experiments", {"experiments", "store", "methods", "metrics", "gpu", "core"}},
    {"reports", {"reports", "experiments", "store", "methods", "metrics", "core", "templates"}},
    {"apps", {"apps", "reports", "experiments", "store", "methods", "metrics", "gpu", "core"}},
};

struct Include {
  std::string file;  // relative to the source folder
  int line = 0;
  std::string target;  // "store/result_store.h"
};

bool is_test(const fs::path& relative) {
  for (const auto& part : relative)
    if (part == "tests") return true;
  return false;
}

std::vector<Include> project_includes() {
  const fs::path root = CAUSTICBENCH_SOURCE_DIR;
  static const std::regex include_line(R"(^\s*#\s*include\s+"([a-z_]+/[^"]+)\")");
  std::vector<Include> includes;
  for (const auto& [folder, allowed] : kMayInclude) {
    for (const auto& entry : fs::recursive_directory_iterator(root / folder)) {
      const fs::path path = entry.path();
      const std::string extension = path.extension().string();
      if (!entry.is_regular_file() || (extension != ".h" && extension != ".cpp" && extension != ".in")) continue;
      const fs::path relative = fs::relative(path, root);
      if (is_test(relative)) continue;
      std::ifstream stream(path);
      std::string text;
      for (int number = 1; std::getline(stream, text); ++number) {
        std::smatch match;
        if (std::regex_search(text, match, include_line)) includes.push_back({relative.string(), number, match[1].str()});
      }
    }
  }
  return includes;
}

std::string first_part(const std::string& path) { return path.substr(0, path.find('/')); }

TEST(Layering, EveryIncludePointsDownOrSideways) {
  const std::vector<Include> includes = project_includes();
  ASSERT_GT(includes.size(), 500u) << "the sources were not found under " << CAUSTICBENCH_SOURCE_DIR;
  std::map<std::string, int> arrows;  // "from -> to": count, for the message
  for (const Include& include : includes) {
    const std::string from = first_part(include.file), to = first_part(include.target);
    ++arrows[from + " -> " + to];
    EXPECT_TRUE(kMayInclude.at(from).count(to))
        << include.file << ":" << include.line << " includes \"" << include.target << "\": " << from
        << "/ may not include " << to << "/ (docs/design.md, \"Layout\")";
  }
  std::string picture;
  for (const auto& [arrow, count] : arrows) picture += "  " + arrow + " (" + std::to_string(count) + ")\n";
  RecordProperty("arrows", picture);
}

// A method's folder includes its own files, methods/*.h and methods/common/, never another method's.
TEST(Layering, AMethodFolderIncludesNoOtherMethodsFolder) {
  static const std::regex method_file(R"(^methods/([a-z_]+)/)");
  size_t checked = 0;
  for (const Include& include : project_includes()) {
    std::smatch from, to;
    if (!std::regex_search(include.file, from, method_file) || from[1] == "common") continue;
    ++checked;
    if (!std::regex_search(include.target, to, method_file)) continue;
    EXPECT_TRUE(to[1] == from[1] || to[1] == "common")
        << include.file << ":" << include.line << " includes \"" << include.target << "\": methods/" << from[1]
        << "/ may include methods/common/ but no other method's folder";
  }
  EXPECT_GT(checked, 100u);
}

}  // namespace
}  // namespace causticbench
