// Strict reading of YAML input files. Every value read is checked for type and range; every map
// remembers which keys the reader asked for, and finish() rejects any other key with a "did you mean"
// suggestion. All errors carry the file, line and column of the offending key or value.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <yaml-cpp/yaml.h>

#include "core/errors.h"

namespace causticbench {

class ConfigNode {
 public:
  // Parses a YAML file; a syntax error or a missing file is an InputError naming the file.
  static ConfigNode load_file(const std::string& path);
  static ConfigNode load_string(const std::string& text, const std::string& name);

  // Shared by every node of one document: its name and, per map (keyed by its byte offset), the keys
  // that readers asked for, so that finish() works on any copy of a node.
  struct Document {
    std::string name;
    std::map<size_t, std::set<std::string>> requested_keys;
  };

  ConfigNode(YAML::Node node, std::shared_ptr<Document> document, std::string path);

  const std::string& file() const { return document_->name; }
  // The dotted path of this node inside the document, e.g. "objects[2].material".
  const std::string& path() const { return path_; }
  SourceLocation location() const;
  SourceLocation location_of(const std::string& key) const;

  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }
  bool has(const std::string& key) const;

  // Map access. `child` requires the key; `optional_child` returns nothing when absent.
  ConfigNode child(const std::string& key) const;
  std::optional<ConfigNode> optional_child(const std::string& key) const;

  // Sequence access.
  size_t size() const;
  ConfigNode at(size_t index) const;

  // Typed scalar values of this node.
  double as_number() const;
  std::string as_string() const;
  bool as_bool() const;

  // Typed values of a key of this map; the `_or` forms return the default when the key is absent.
  double number(const std::string& key, double min_value, double max_value) const;
  double number_or(const std::string& key, double fallback, double min_value, double max_value) const;
  int integer(const std::string& key, int min_value, int max_value) const;
  int integer_or(const std::string& key, int fallback, int min_value, int max_value) const;
  bool boolean_or(const std::string& key, bool fallback) const;
  std::string string(const std::string& key) const;
  std::string string_or(const std::string& key, const std::string& fallback) const;
  std::string choice(const std::string& key, const std::vector<std::string>& options) const;
  std::string choice_or(const std::string& key, const std::string& fallback,
                        const std::vector<std::string>& options) const;
  glm::dvec3 vec3(const std::string& key) const;
  glm::dvec3 vec3_or(const std::string& key, glm::dvec3 fallback) const;
  // An RGB triple, or a single number meaning grey; each component within [min, max].
  glm::dvec3 rgb(const std::string& key, double min_value, double max_value) const;
  glm::dvec3 rgb_or(const std::string& key, glm::dvec3 fallback, double min_value, double max_value) const;
  std::vector<double> numbers(const std::string& key, size_t count, double min_value, double max_value) const;

  // Rejects keys of this map that no reader asked for.
  void finish() const;
  // The keys present in this map, in file order.
  std::vector<std::string> keys() const;

  [[noreturn]] void fail(const std::string& key, const std::string& expected, const std::string& found) const;
  [[noreturn]] void fail_here(const std::string& expected, const std::string& found) const;

  std::string describe_value() const;

 private:
  void require_map() const;
  double number_value(const ConfigNode& value, const std::string& key, double min_value, double max_value) const;

  std::set<std::string>& requested_keys() const;

  YAML::Node node_;
  std::shared_ptr<Document> document_;
  std::string path_;
};

}  // namespace causticbench
