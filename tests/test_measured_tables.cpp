// Every number a method's README quotes in a "Measured" table names what produces it (issue 51): a test
// (`Suite.Name`, a build/tests/ command or a test source), a shipped experiment or scene file, a
// `causticbench` command or a script of the suite. The name may stand in the row, in the paragraph that
// introduces the table (its caption), or in the row before it when the row says "the same". A file of
// /tmp is no producer: a reader does not have it, so a figure measured on one is a figure nobody can
// rerun. And every configuration file a document names is shipped, so that a named experiment is one
// a reader can run. That the named tests exist and that their filters select tests is
// tests/test_documented_tests.cpp's; that the cheap experiments still reproduce what the READMEs quote
// from them is tests/test_quoted_experiments.cpp's.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace causticbench {
namespace {

namespace fs = std::filesystem;

const fs::path kRoot = CAUSTICBENCH_SOURCE_DIR;

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// One Markdown table: the heading it stands under, the paragraph just before it, and its data rows
// (line number, text), the header and the separator left out.
struct Table {
  std::string heading, caption;
  std::vector<std::pair<size_t, std::string>> rows;
};

std::vector<Table> tables_of(const std::string& text) {
  std::vector<Table> tables;
  std::string heading, paragraph;
  bool in_code = false, in_table = false, header_seen = false;
  const std::vector<std::string> lines = lines_of(text);
  for (size_t index = 0; index < lines.size(); ++index) {
    const std::string& line = lines[index];
    if (line.rfind("```", 0) == 0) in_code = !in_code;
    if (in_code) continue;
    if (line.rfind("#", 0) == 0) {
      heading = line;
      paragraph.clear();
      in_table = false;
      continue;
    }
    if (line.rfind("|", 0) != 0) {
      if (in_table) paragraph.clear();
      in_table = false;
      if (line.find_first_not_of(' ') == std::string::npos) {
        if (!paragraph.empty() && paragraph.back() != '\n') paragraph += '\n';  // a blank line ends it
      } else {
        if (!paragraph.empty() && paragraph.back() == '\n') paragraph.clear();  // a new paragraph begins
        paragraph += line + ' ';
      }
      continue;
    }
    if (!in_table) {
      tables.push_back(Table{heading, paragraph, {}});
      in_table = true;
      header_seen = false;
      continue;  // the header row
    }
    static const std::regex separator("^\\|[-:| ]+\\|\\s*$");
    if (!header_seen && std::regex_match(line, separator)) {
      header_seen = true;
      continue;
    }
    tables.back().rows.emplace_back(index + 1, line);
  }
  return tables;
}

// What produces a figure: a test's name, a test executable or source, a shipped experiment or scene
// file, a causticbench command, a script of the suite.
bool names_a_producer(const std::string& text) {
  static const std::regex producer(
      "`[A-Z][A-Za-z0-9]*\\.[A-Z*][A-Za-z0-9_*]*`"  // Suite.Name
      "|build/tests/test_|\\btests/test_[a-z0-9_]+\\.cpp|\\btest_[a-z0-9_]+\\b"
      "|\\b[a-z0-9_]+\\.yaml\\b"                        // an experiment or scene (shipped: the test below)
      "|\\bcausticbench(-gpubench)?\\s|scripts/[a-z_]+\\.(py|sh)");
  return std::regex_search(text, producer);
}

// A file of /tmp named as what a figure was measured on ("render /tmp/ms.yaml").
bool names_a_temporary_file(const std::string& text) {
  static const std::regex temporary("/tmp/[^\\s`|]*\\.yaml");
  return std::regex_search(text, temporary);
}

bool says_the_same(const std::string& row) {
  static const std::regex same("\\b[Tt]he same\\b");
  return std::regex_search(row, same);
}

std::vector<fs::path> method_readmes() {
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(kRoot / "methods"))
    if (fs::is_regular_file(entry.path() / "README.md")) files.push_back(entry.path() / "README.md");
  return files;
}

TEST(MeasuredTables, TheTablesAreFound) {
  // The parser on a known document: a caption that names an experiment, rows that name tests.
  const std::vector<Table> tables = tables_of(
      "## Measured\n\nFrom `configs/experiments/x.yaml`:\n\n| a | b |\n|---|---|\n| one | 1 |\n| two | 2 |\n\n"
      "Text.\n\n| what | command |\n|---|---|\n| it | `build/tests/test_it` |\n\n```\n| not | a table |\n```\n");
  ASSERT_EQ(tables.size(), 2u);
  EXPECT_EQ(tables[0].rows.size(), 2u);
  EXPECT_TRUE(names_a_producer(tables[0].caption)) << tables[0].caption;
  EXPECT_EQ(tables[1].caption, "Text. \n");
  EXPECT_FALSE(names_a_producer(tables[1].caption));
  EXPECT_TRUE(names_a_producer(tables[1].rows[0].second));
  EXPECT_TRUE(names_a_temporary_file("`causticbench -q render /tmp/ms.yaml --method pinhole`"));
  EXPECT_FALSE(names_a_temporary_file("`causticbench -q render configs/scenes/ring.yaml -o /tmp/x`"));
  size_t measured = 0;
  for (const fs::path& file : method_readmes())
    for (const Table& table : tables_of(read(file)))
      if (table.heading.find("easured") != std::string::npos) measured += table.rows.size();
  EXPECT_GT(measured, 100u) << "the method READMEs' Measured tables were not found";
}

TEST(MeasuredTables, EveryRowNamesWhatProducesIt) {
  for (const fs::path& file : method_readmes()) {
    const std::string where = fs::relative(file, kRoot).string();
    for (const Table& table : tables_of(read(file))) {
      if (table.heading.find("easured") == std::string::npos) continue;
      const bool caption_names = names_a_producer(table.caption);
      EXPECT_FALSE(names_a_temporary_file(table.caption))
          << where << ": the paragraph before the table at line " << table.rows.front().first
          << " names a file of /tmp; ship it (configs/experiments/, configs/scenes/) or name a test";
      bool previous_named = caption_names;
      for (const auto& [line, row] : table.rows) {
        const bool named = names_a_producer(row) || caption_names || (previous_named && says_the_same(row));
        EXPECT_TRUE(named) << where << ":" << line
                           << ": a measured row names no test, experiment, command or script that produces it:\n"
                           << row;
        EXPECT_FALSE(names_a_temporary_file(row))
            << where << ":" << line << ": the row's figures come from a file of /tmp; ship it or name a test:\n"
            << row;
        previous_named = named;
      }
    }
  }
}

std::vector<fs::path> documents() {
  std::vector<fs::path> files = {kRoot / "README.md"};
  for (const fs::path& folder : {kRoot / "docs", kRoot / "methods"})
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(folder))
      if (entry.path().extension() == ".md") files.push_back(entry.path());
  return files;
}

// The names of every YAML file the suite ships (configs/, examples/, tests/).
const std::vector<std::string>& shipped_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> found;
    for (const char* folder : {"configs", "examples", "tests"})
      for (const fs::directory_entry& entry : fs::recursive_directory_iterator(kRoot / folder))
        if (entry.path().extension() == ".yaml") found.push_back(entry.path().filename().string());
    return found;
  }();
  return names;
}

TEST(MeasuredTables, EveryConfigurationFileADocumentNamesIsShipped) {
  // A path from the repository's root (configs/experiments/x.yaml) exists; a bare name (`x.yaml`) is the
  // name of a shipped file. Placeholders (NAME, EXPERIMENT) and patterns (*) stand for no one file.
  const std::regex named("(^|[^\\w/.*-])((?:[\\w.-]+/)*[\\w.-]+\\.yaml)\\b");
  const std::regex placeholder("[A-Z]{3,}|\\*");
  size_t files = 0;
  for (const fs::path& file : documents()) {
    const std::string text = read(file);
    for (std::sregex_iterator match(text.begin(), text.end(), named), end; match != end; ++match) {
      const std::string path = (*match)[2].str();
      if (std::regex_search(path, placeholder)) continue;
      const std::string at = fs::relative(file, kRoot).string() + ":" +
                             std::to_string(1 + std::count(text.begin(), text.begin() + match->position(2), '\n'));
      if (path.find('/') != std::string::npos) {
        if (path.rfind("configs/", 0) != 0 && path.rfind("examples/", 0) != 0) continue;  // relative or elsewhere
        ++files;
        EXPECT_TRUE(fs::is_regular_file(kRoot / path)) << at << " names " << path << ", which is not shipped";
      } else {
        ++files;
        const bool shipped = std::find(shipped_names().begin(), shipped_names().end(), path) != shipped_names().end();
        EXPECT_TRUE(shipped) << at << " names " << path << ", which no shipped configuration file is called";
      }
    }
  }
  EXPECT_GT(files, 100u) << "the documents' configuration files were not found";
}

// Whether `name` matches `pattern`, whose '*' stands for any text (wand2003_fig6_*.yaml).
bool matches_pattern(const std::string& name, const std::string& pattern) {
  const size_t star = pattern.find('*');
  if (star == std::string::npos) return name == pattern;
  const std::string head = pattern.substr(0, star), tail = pattern.substr(star + 1);
  return name.size() >= head.size() + tail.size() && name.compare(0, head.size(), head) == 0 &&
         name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
}

TEST(MeasuredTables, EveryShippedExperimentIsNamedByADocument) {
  // An experiment no document names is one a reader cannot find, and one whose output nobody quotes.
  std::string all;
  for (const fs::path& file : documents()) all += read(file) + "\n";
  std::vector<std::string> patterns;
  const std::regex pattern("[\\w.-]{3,}\\*[\\w.-]*\\.yaml");  // a prefix of its own: "*.yaml" names no one file
  for (std::sregex_iterator match(all.begin(), all.end(), pattern), end; match != end; ++match)
    patterns.push_back(match->str());
  size_t experiments = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(kRoot / "configs" / "experiments")) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".yaml") continue;
    ++experiments;
    const bool named = all.find(name) != std::string::npos ||
                       std::any_of(patterns.begin(), patterns.end(),
                                   [&](const std::string& candidate) { return matches_pattern(name, candidate); });
    EXPECT_TRUE(named) << "configs/experiments/" << name << " is named by no document (README.md, docs/, a method's README)";
  }
  EXPECT_GT(experiments, 40u);
}

}  // namespace
}  // namespace causticbench
