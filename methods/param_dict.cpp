#include "methods/param_dict.h"

#include <cctype>
#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <regex>

#include <fmt/format.h>

namespace causticbench {

ParamSpec ParamSpec::integer(std::string name, int64_t fallback, double min_value, double max_value,
                             std::string meaning, ParamPhase phase) {
  return ParamSpec{std::move(name), ParamType::integer, fallback, min_value, max_value, {}, std::move(meaning), phase,
                   std::nullopt, true, std::nullopt, false};
}
ParamSpec ParamSpec::real(std::string name, double fallback, double min_value, double max_value, std::string meaning,
                          ParamPhase phase) {
  return ParamSpec{std::move(name), ParamType::real, fallback, min_value, max_value, {}, std::move(meaning), phase,
                   std::nullopt, true, std::nullopt, false};
}
ParamSpec ParamSpec::boolean(std::string name, bool fallback, std::string meaning, ParamPhase phase) {
  return ParamSpec{std::move(name), ParamType::boolean, fallback, 0, 1, {}, std::move(meaning), phase, std::nullopt, true, std::nullopt, false};
}
ParamSpec ParamSpec::choice(std::string name, std::string fallback, std::vector<std::string> choices,
                            std::string meaning, ParamPhase phase) {
  return ParamSpec{std::move(name), ParamType::choice, std::move(fallback), 0, 0, std::move(choices),
                   std::move(meaning), phase, std::nullopt, true, std::nullopt, false};
}

ParamSpec ParamSpec::text(std::string name, std::string fallback, std::string meaning, ParamPhase phase) {
  return ParamSpec{std::move(name), ParamType::text, std::move(fallback), 0, 0, {}, std::move(meaning), phase,
                   std::nullopt, true, std::nullopt, false};
}

ParamSpec ParamSpec::family_of(std::string prefix, std::string meaning, ParamPhase phase) {
  ParamSpec spec = text(std::move(prefix), "", std::move(meaning), phase);
  spec.family = true;
  return spec;
}

namespace {
bool is_word(const std::string& text) {
  if (text.empty()) return false;
  for (char c : text)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}
}  // namespace

bool ParamSpec::covers(const std::string& key) const {
  if (!family) return key == name;
  return key.size() > name.size() && key.compare(0, name.size(), name) == 0 && is_word(key.substr(name.size()));
}

const ParamSpec* find_param_spec(const std::vector<ParamSpec>& specs, const std::string& key) {
  for (const ParamSpec& spec : specs)
    if (spec.covers(key)) return &spec;
  return nullptr;
}

std::string phase_name(ParamPhase phase) {
  switch (phase) {
    case ParamPhase::build: return "build";
    case ParamPhase::frame: return "frame";
    case ParamPhase::render: return "render";
  }
  return "?";
}

ParamSpec& ParamSpec::only_when(std::string knob, std::vector<std::string> values) {
  applies_when = ParamCondition{std::move(knob), std::move(values)};
  return *this;
}

ParamSpec& ParamSpec::or_special(double value) {
  special_value = value;
  return *this;
}

ParamSpec& ParamSpec::auto_by_default() {
  accepts_auto = true;
  default_value = std::string("auto");
  return *this;
}

ParamSpec& ParamSpec::unkeyed_at_default() {
  keyed_at_default = false;
  return *this;
}

std::string ParamSpec::condition_text() const {
  if (!applies_when) return "";
  return applies_when->knob + (applies_when->values.size() == 1 ? " is " : " is one of ") + join(applies_when->values, ", ");
}

std::string ParamSpec::type_name() const {
  switch (type) {
    case ParamType::integer: return "integer";
    case ParamType::real: return "real";
    case ParamType::boolean: return "boolean";
    case ParamType::choice: return "choice";
    case ParamType::text: return family ? "any" : "text";
  }
  return "?";
}

std::string ParamSpec::range_text() const {
  switch (type) {
    case ParamType::integer:
    case ParamType::real:
      if (accepts_auto) return fmt::format("auto or [{}, {}]", min_value, max_value);
      return special_value ? fmt::format("{} or [{}, {}]", *special_value, min_value, max_value)
                           : fmt::format("[{}, {}]", min_value, max_value);
    case ParamType::boolean: return "true, false";
    case ParamType::choice: return join(choices, ", ");
    case ParamType::text: return family ? "an integer, a number, true, false or text" : "any text";
  }
  return "";
}

std::string format_param_value(const ParamValue& value) {
  return std::visit([](const auto& v) -> std::string {
    using T = std::decay_t<decltype(v)>;
    if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
    else if constexpr (std::is_same_v<T, std::string>) return v;
    else return fmt::format("{}", v);
  }, value);
}

const ParamValue& ParamSet::get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) throw std::logic_error("parameter '" + name + "' was not declared by the method");
  return it->second;
}
int64_t ParamSet::integer(const std::string& name) const { return std::get<int64_t>(get(name)); }
double ParamSet::real(const std::string& name) const { return std::get<double>(get(name)); }
bool ParamSet::boolean(const std::string& name) const { return std::get<bool>(get(name)); }
const std::string& ParamSet::text(const std::string& name) const { return std::get<std::string>(get(name)); }

nlohmann::json ParamSet::to_json() const {
  nlohmann::json result = nlohmann::json::object();
  for (const auto& [name, value] : values_) {
    std::visit([&](const auto& v) { result[name] = v; }, value);
  }
  return result;
}

nlohmann::json ParamSet::key_json(const std::vector<ParamSpec>& specs) const {
  nlohmann::json result = to_json();
  for (const ParamSpec& spec : specs) {
    auto it = values_.find(spec.name);
    if (!spec.keyed_at_default && it != values_.end() && it->second == spec.default_value) result.erase(spec.name);
  }
  return result;
}

void ParamDict::set(const std::string& key, const std::string& text, const SourceLocation& where) {
  entries_[key] = Entry{text, where};
}

void ParamDict::set_assignment(const std::string& assignment, const std::string& origin) {
  size_t equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw InputError(fmt::format("{}: expected key=value, found '{}'", origin, assignment));
  }
  set(assignment.substr(0, equals), assignment.substr(equals + 1), SourceLocation{origin, 0, 0});
}

void ParamDict::set_from_config(const ConfigNode& map) {
  for (const std::string& key : map.keys()) {
    ConfigNode value = map.child(key);
    set(key, value.as_string(), value.location());
  }
}

namespace {
// Decimal only, as the YAML reader reads numbers: strtod alone would also take hex ("0x10"), leading
// blanks and "infinity", so that --set and a YAML file would disagree on what is a number.
const std::regex& decimal_number() {
  static const std::regex decimal(R"([+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?)");
  return decimal;
}

ParamValue typed_by_text(const std::string& text) {
  if (text == "true") return true;
  if (text == "false") return false;
  static const std::regex whole(R"([+-]?[0-9]{1,18})");
  if (std::regex_match(text, whole)) return static_cast<int64_t>(std::stoll(text));
  if (std::regex_match(text, decimal_number())) {
    double number = std::strtod(text.c_str(), nullptr);
    // One number, one value: 1e4, 10000.0 and 10000 are the integer 10000 (the same key, and the same
    // text for the program that receives it).
    if (std::isfinite(number) && number == std::floor(number) && std::abs(number) < 9007199254740992.0)
      return static_cast<int64_t>(number);
    if (std::isfinite(number)) return number;
  }
  return text;
}
}  // namespace

ParamSet ParamDict::resolve(const std::vector<ParamSpec>& specs, const std::string& owner,
                            const std::set<std::string>& droppable) const {
  std::vector<std::string> names;
  for (const ParamSpec& spec : specs) names.push_back(spec.family ? spec.name + "<name>" : spec.name);
  for (const auto& [key, entry] : entries_) {
    if (!find_param_spec(specs, key)) {
      std::string prefix = entry.where.describe();
      throw InputError(fmt::format("{}{}unknown parameter '{}' for method '{}'{}; its parameters: {}", prefix,
                                   prefix.empty() ? "" : ": ", key, owner, did_you_mean(key, names), join(names, ", ")));
    }
  }
  ParamSet result;
  for (const ParamSpec& spec : specs) {
    if (spec.family) {
      // Its members as set; typed by their text (ParamSpec::family), so that a swept program knob is
      // a number in the run key, a claim's x and a filter.
      for (const auto& [key, entry] : entries_)
        if (spec.covers(key)) result.set(key, typed_by_text(entry.text));
      continue;
    }
    auto it = entries_.find(spec.name);
    if (spec.applies_when) {
      // The controlling knob is declared earlier, so it is resolved (or itself does not apply).
      const ParamCondition& condition = *spec.applies_when;
      bool applies = result.has(condition.knob) &&
                     std::find(condition.values.begin(), condition.values.end(),
                               format_param_value(result.values().at(condition.knob))) != condition.values.end();
      if (!applies) {
        if (it != entries_.end() && !droppable.count(spec.name)) {
          std::string found = result.has(condition.knob)
                                  ? condition.knob + " is " + format_param_value(result.values().at(condition.knob))
                                  : condition.knob + " does not apply either";
          throw_input_error(it->second.where, owner + "." + spec.name,
                            fmt::format("'{}' only where it applies ({}): remove it, or set {}", spec.name,
                                        spec.condition_text(), spec.condition_text()),
                            found);
        }
        continue;
      }
    }
    if (it == entries_.end()) {
      result.set(spec.name, spec.default_value);
      continue;
    }
    const std::string& text = it->second.text;
    const SourceLocation& where = it->second.where;
    auto fail = [&](const std::string& expected) {
      throw_input_error(where, owner + "." + spec.name, expected, "'" + text + "'");
    };
    switch (spec.type) {
      case ParamType::text:
        result.set(spec.name, text);
        break;
      case ParamType::boolean:
        if (text == "true" || text == "yes" || text == "on") result.set(spec.name, true);
        else if (text == "false" || text == "no" || text == "off") result.set(spec.name, false);
        else fail("true or false");
        break;
      case ParamType::choice: {
        bool found = false;
        for (const std::string& option : spec.choices) found = found || option == text;
        if (!found) fail("one of " + join(spec.choices, ", ") + did_you_mean(text, spec.choices));
        result.set(spec.name, text);
        break;
      }
      case ParamType::integer:
      case ParamType::real: {
        if (spec.accepts_auto && text == "auto") {
          result.set(spec.name, std::string("auto"));
          break;
        }
        if (!std::regex_match(text, decimal_number()))
          fail(std::string(spec.accepts_auto ? "auto or " : "") + (spec.type == ParamType::integer ? "an integer" : "a decimal number"));
        double number = std::strtod(text.c_str(), nullptr);
        if (!std::isfinite(number)) fail("a finite number");
        bool special = spec.special_value && number == *spec.special_value;
        if (!special && (number < spec.min_value || number > spec.max_value))
          fail(spec.special_value || spec.accepts_auto ? spec.range_text() : "a value in " + spec.range_text());
        if (spec.type == ParamType::integer) {
          if (std::floor(number) != number) fail("an integer");
          result.set(spec.name, static_cast<int64_t>(number));
        } else {
          result.set(spec.name, number);
        }
        break;
      }
    }
  }
  return result;
}

ParamSet select_phase(const ParamSet& all, const std::vector<ParamSpec>& specs, ParamPhase phase) {
  ParamSet result;
  for (const auto& [key, value] : all.values()) {
    const ParamSpec* spec = find_param_spec(specs, key);
    if (spec && spec->phase == phase) result.set(key, value);
  }
  return result;
}

}  // namespace causticbench
