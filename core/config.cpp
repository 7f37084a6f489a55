#include "core/config.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "core/files.h"

namespace causticbench {

namespace {

std::string scalar_text(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing";
  if (node.IsScalar()) return fmt::format("'{}'", node.Scalar());
  if (node.IsSequence()) return fmt::format("a list of {} items", node.size());
  if (node.IsMap()) return "a map";
  return "an unknown value";
}

std::string format_range(double min_value, double max_value) {
  const double unbounded = 1e300;
  if (min_value <= -unbounded && max_value >= unbounded) return "a finite number";
  if (max_value >= unbounded) return fmt::format("a number >= {}", min_value);
  if (min_value <= -unbounded) return fmt::format("a number <= {}", max_value);
  return fmt::format("a number in [{}, {}]", min_value, max_value);
}

SourceLocation location_of_mark(const std::string& file, const YAML::Mark& mark) {
  return SourceLocation{file, mark.line + 1, mark.column + 1};
}

std::string where_in(const std::string& path) { return path.empty() ? "at the top level" : "in '" + path + "'"; }

// yaml-cpp keeps every pair of a map whose key repeats, but node[key] finds only the first: the
// second value would be ignored without a word. So every map of the document is checked once, at
// load, before any reader looks at it. `visited` holds the byte offsets of the maps and lists already
// checked, so that an alias is not walked again.
void reject_duplicate_keys(const YAML::Node& node, const std::string& file, const std::string& path,
                           std::set<size_t>& visited) {
  if (!node.IsMap() && !node.IsSequence()) return;
  if (!visited.insert(node.Mark().pos).second) return;
  if (node.IsSequence()) {
    for (size_t i = 0; i < node.size(); ++i) {
      reject_duplicate_keys(node[i], file, fmt::format("{}[{}]", path, i), visited);
    }
    return;
  }
  std::map<std::string, YAML::Mark> first_seen;
  for (auto it = node.begin(); it != node.end(); ++it) {
    SourceLocation here = location_of_mark(file, it->first.Mark());
    if (!it->first.IsScalar()) {
      throw InputError(fmt::format("{}: expected a key that is a plain word {}, found {}", here.describe(),
                                   where_in(path), scalar_text(it->first)));
    }
    std::string key = it->first.Scalar();
    auto [earlier, inserted] = first_seen.insert({key, it->first.Mark()});
    if (!inserted) {
      throw InputError(fmt::format("{}: duplicate key '{}' {}: first at {}, again at {}; give each key once",
                                   here.describe(), key, where_in(path),
                                   location_of_mark(file, earlier->second).describe(), here.describe()));
    }
    reject_duplicate_keys(it->second, file, path.empty() ? key : path + "." + key, visited);
  }
}

}  // namespace

ConfigNode ConfigNode::load_file(const std::string& path) { return load_string(read_text(path), path); }

ConfigNode ConfigNode::load_string(const std::string& text, const std::string& name) {
  try {
    YAML::Node root = YAML::Load(text);
    std::set<size_t> visited;
    reject_duplicate_keys(root, name, "", visited);
    auto document = std::make_shared<Document>();
    document->name = name;
    return ConfigNode(root, document, "");
  } catch (const YAML::ParserException& error) {
    SourceLocation where{name, error.mark.line + 1, error.mark.column + 1};
    throw InputError(fmt::format("{}: YAML syntax error: {}", where.describe(), error.msg));
  }
}

ConfigNode::ConfigNode(YAML::Node node, std::shared_ptr<Document> document, std::string path)
    : node_(std::move(node)), document_(std::move(document)), path_(std::move(path)) {}

std::set<std::string>& ConfigNode::requested_keys() const {
  return document_->requested_keys[node_.Mark().pos];
}

SourceLocation ConfigNode::location() const {
  YAML::Mark mark = node_.Mark();
  if (mark.is_null()) return SourceLocation{document_->name, 0, 0};
  return SourceLocation{document_->name, mark.line + 1, mark.column + 1};
}

SourceLocation ConfigNode::location_of(const std::string& key) const {
  if (node_.IsMap()) {
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      if (it->first.IsScalar() && it->first.Scalar() == key) {
        YAML::Mark mark = it->first.Mark();
        return SourceLocation{document_->name, mark.line + 1, mark.column + 1};
      }
    }
  }
  return location();
}

void ConfigNode::require_map() const {
  if (!node_.IsMap()) {
    throw_input_error(location(), path_, "a map of 'key: value' entries", scalar_text(node_));
  }
}

bool ConfigNode::has(const std::string& key) const {
  requested_keys().insert(key);
  if (!node_.IsMap()) return false;
  YAML::Node value = node_[key];
  return value.IsDefined() && !value.IsNull();
}

ConfigNode ConfigNode::child(const std::string& key) const {
  require_map();
  requested_keys().insert(key);
  YAML::Node value = node_[key];
  std::string child_path = path_.empty() ? key : path_ + "." + key;
  if (!value.IsDefined() || value.IsNull()) {
    throw_input_error(location(), child_path, fmt::format("a value for the required key '{}'", key), "none");
  }
  return ConfigNode(value, document_, child_path);
}

std::optional<ConfigNode> ConfigNode::optional_child(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return child(key);
}

size_t ConfigNode::size() const {
  if (!node_.IsSequence()) throw_input_error(location(), path_, "a list", scalar_text(node_));
  return node_.size();
}

ConfigNode ConfigNode::at(size_t index) const {
  size();
  return ConfigNode(node_[index], document_, fmt::format("{}[{}]", path_, index));
}

std::string ConfigNode::describe_value() const { return scalar_text(node_); }

double ConfigNode::as_number() const {
  if (!node_.IsScalar()) throw_input_error(location(), path_, "a number", scalar_text(node_));
  double value = 0.0;
  try {
    value = node_.as<double>();
  } catch (const YAML::Exception&) {
    throw_input_error(location(), path_, "a number", scalar_text(node_));
  }
  if (!std::isfinite(value)) throw_input_error(location(), path_, "a finite number", scalar_text(node_));
  return value;
}

std::string ConfigNode::as_string() const {
  if (!node_.IsScalar()) throw_input_error(location(), path_, "a text value", scalar_text(node_));
  return node_.Scalar();
}

bool ConfigNode::as_bool() const {
  if (node_.IsScalar()) {
    try {
      return node_.as<bool>();
    } catch (const YAML::Exception&) {
    }
  }
  throw_input_error(location(), path_, "true or false", scalar_text(node_));
}

double ConfigNode::number_value(const ConfigNode& value, const std::string& key, double min_value,
                                double max_value) const {
  double number = value.as_number();
  if (number < min_value || number > max_value) {
    throw_input_error(value.location(), value.path(), format_range(min_value, max_value), scalar_text(value.node_));
  }
  return number;
}

double ConfigNode::number(const std::string& key, double min_value, double max_value) const {
  return number_value(child(key), key, min_value, max_value);
}

double ConfigNode::number_or(const std::string& key, double fallback, double min_value, double max_value) const {
  if (!has(key)) return fallback;
  return number(key, min_value, max_value);
}

int ConfigNode::integer(const std::string& key, int min_value, int max_value) const {
  ConfigNode value = child(key);
  double number = number_value(value, key, min_value, max_value);
  if (std::floor(number) != number) throw_input_error(value.location(), value.path(), "a whole number", scalar_text(value.node_));
  return static_cast<int>(number);
}

int ConfigNode::integer_or(const std::string& key, int fallback, int min_value, int max_value) const {
  if (!has(key)) return fallback;
  return integer(key, min_value, max_value);
}

bool ConfigNode::boolean_or(const std::string& key, bool fallback) const {
  if (!has(key)) return fallback;
  return child(key).as_bool();
}

std::string ConfigNode::string(const std::string& key) const { return child(key).as_string(); }

std::string ConfigNode::string_or(const std::string& key, const std::string& fallback) const {
  if (!has(key)) return fallback;
  return string(key);
}

std::string ConfigNode::choice(const std::string& key, const std::vector<std::string>& options) const {
  ConfigNode value = child(key);
  std::string text = value.as_string();
  for (const std::string& option : options) {
    if (option == text) return text;
  }
  throw_input_error(value.location(), value.path(), "one of " + join(options, ", ") + did_you_mean(text, options),
                    scalar_text(value.node_));
}

std::string ConfigNode::choice_or(const std::string& key, const std::string& fallback,
                                  const std::vector<std::string>& options) const {
  if (!has(key)) return fallback;
  return choice(key, options);
}

std::vector<double> ConfigNode::numbers(const std::string& key, size_t count, double min_value,
                                        double max_value) const {
  ConfigNode value = child(key);
  if (!value.is_sequence() || value.size() != count) {
    throw_input_error(value.location(), value.path(), fmt::format("a list of {} numbers", count), value.describe_value());
  }
  std::vector<double> result;
  for (size_t i = 0; i < count; ++i) result.push_back(number_value(value.at(i), key, min_value, max_value));
  return result;
}

glm::dvec3 ConfigNode::vec3(const std::string& key) const {
  std::vector<double> values = numbers(key, 3, -1e300, 1e300);
  return glm::dvec3(values[0], values[1], values[2]);
}

glm::dvec3 ConfigNode::vec3_or(const std::string& key, glm::dvec3 fallback) const {
  if (!has(key)) return fallback;
  return vec3(key);
}

glm::dvec3 ConfigNode::rgb(const std::string& key, double min_value, double max_value) const {
  ConfigNode value = child(key);
  if (value.is_scalar()) {
    double grey = number_value(value, key, min_value, max_value);
    return glm::dvec3(grey);
  }
  std::vector<double> values = numbers(key, 3, min_value, max_value);
  return glm::dvec3(values[0], values[1], values[2]);
}

glm::dvec3 ConfigNode::rgb_or(const std::string& key, glm::dvec3 fallback, double min_value, double max_value) const {
  if (!has(key)) return fallback;
  return rgb(key, min_value, max_value);
}

std::vector<std::string> ConfigNode::keys() const {
  std::vector<std::string> result;
  if (!node_.IsMap()) return result;
  for (auto it = node_.begin(); it != node_.end(); ++it) result.push_back(it->first.Scalar());
  return result;
}

void ConfigNode::finish() const {
  if (!node_.IsMap()) return;
  const std::set<std::string>& requested = requested_keys();
  std::vector<std::string> known(requested.begin(), requested.end());
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    std::string key = it->first.Scalar();
    if (requested.count(key)) continue;
    SourceLocation where = location_of_mark(document_->name, it->first.Mark());
    throw InputError(fmt::format("{}: unknown key '{}' {}{}; known keys: {}", where.describe(), key, where_in(path_),
                                 did_you_mean(key, known), join(known, ", ")));
  }
}

void ConfigNode::fail(const std::string& key, const std::string& expected, const std::string& found) const {
  std::string key_path = path_.empty() ? key : path_ + "." + key;
  throw_input_error(location_of(key), key_path, expected, found);
}

void ConfigNode::fail_here(const std::string& expected, const std::string& found) const {
  throw_input_error(location(), path_, expected, found);
}

}  // namespace causticbench
