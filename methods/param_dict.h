// Knobs. A method declares a ParamSpec per knob; values arrive as a ParamDict of text with the place
// each came from (a YAML line or the command line), and resolve() checks them against the specs:
// unknown keys fail with "did you mean", wrong types and out-of-range values fail with the file,
// line and what was expected.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/config.h"
#include "core/errors.h"

namespace causticbench {

// `text`: any string (external's `command`). A family (ParamSpec::family) holds the knobs a method passes
// on without knowing them: each value is typed by its text (see ParamSpec::family).
enum class ParamType { integer, real, boolean, choice, text };
// The three phases of a method's life (docs/design.md, "Knob phases"): build knobs feed prepare() and
// are fixed for the life of a prepared instance; frame knobs feed update() (interpolation and blending
// choices, per-frame sampling), so runs that differ only in them share one prepare(); render knobs
// feed render(), so runs that differ only in them also share update().
enum class ParamPhase { build, frame, render };
std::string phase_name(ParamPhase phase);

// When a knob applies: only while another knob (a choice or boolean declared before it) has one of
// the listed values, as `sh_order` only under `storage: sh`. A knob that does not apply is an error
// when set, is absent from the resolved ParamSet and so from the run key.
struct ParamCondition {
  std::string knob;
  std::vector<std::string> values;
};

using ParamValue = std::variant<bool, int64_t, double, std::string>;

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::real;
  ParamValue default_value;
  double min_value = 0.0;
  double max_value = 0.0;
  std::vector<std::string> choices;
  std::string meaning;
  ParamPhase phase = ParamPhase::render;
  std::optional<ParamCondition> applies_when;  // none: always applies
  // False for a knob added after experiments shipped whose default changes nothing they measured: at its
  // default it is left out of the run key (ParamSet::key_json), so those runs keep their keys and results.
  bool keyed_at_default = true;
  // A numeric knob's one value outside [min_value, max_value] that means something of its own (pinhole's
  // `epsilon: -1`, "automatic"); values between it and the range are refused, not read as it.
  std::optional<double> special_value;
  // A numeric knob whose value is derived from the scene at prepare() unless set: it also takes the word
  // `auto` (its default), which the resolved ParamSet holds as the text "auto" (ParamSet::is_auto).
  bool accepts_auto = false;
  // A family of knobs rather than one: `name` is a prefix ("program."), and every knob whose name is the
  // prefix and a word (letters, digits, '_') belongs to it, with any value and without a default. Each
  // value is typed by its text: an integral number (7, 1e4, 2.0) is an integer, another decimal number a
  // real, true and false booleans, anything else text; so that equal numbers are one value. What a
  // method passes on to a program it runs (external's `program.*`): the method cannot list the program's
  // knobs, yet they are in the run key, sweeps and filters like any other.
  bool family = false;

  static ParamSpec integer(std::string name, int64_t fallback, double min_value, double max_value, std::string meaning,
                           ParamPhase phase);
  static ParamSpec real(std::string name, double fallback, double min_value, double max_value, std::string meaning,
                        ParamPhase phase);
  static ParamSpec boolean(std::string name, bool fallback, std::string meaning, ParamPhase phase);
  static ParamSpec choice(std::string name, std::string fallback, std::vector<std::string> choices, std::string meaning,
                          ParamPhase phase);
  static ParamSpec text(std::string name, std::string fallback, std::string meaning, ParamPhase phase);
  // The family of knobs `prefix`<word> (see `family`).
  static ParamSpec family_of(std::string prefix, std::string meaning, ParamPhase phase);

  // Whether knob `key` is this knob, or a member of this family.
  bool covers(const std::string& key) const;

  // Declares when the knob applies (see ParamCondition); returns *this for chaining on a factory.
  ParamSpec& only_when(std::string knob, std::vector<std::string> values);
  // Sets keyed_at_default to false; returns *this.
  ParamSpec& unkeyed_at_default();
  // Sets special_value; returns *this.
  ParamSpec& or_special(double value);
  // Makes `auto` a value of this numeric knob and its default (accepts_auto); returns *this.
  ParamSpec& auto_by_default();

  std::string type_name() const;
  std::string range_text() const;
  // "storage is sh", or "" when the knob always applies.
  std::string condition_text() const;
};

std::string format_param_value(const ParamValue& value);

// The spec of knob `key` among `specs` (the knob's own, or its family's), or nullptr.
const ParamSpec* find_param_spec(const std::vector<ParamSpec>& specs, const std::string& key);

// Resolved, typed knob values.
class ParamSet {
 public:
  int64_t integer(const std::string& name) const;
  double real(const std::string& name) const;
  bool boolean(const std::string& name) const;
  const std::string& text(const std::string& name) const;
  // A knob declared with auto_by_default() that holds `auto` rather than a number.
  bool is_auto(const std::string& name) const { return std::holds_alternative<std::string>(get(name)); }
  void set(const std::string& name, ParamValue value) { values_[name] = std::move(value); }
  bool has(const std::string& name) const { return values_.count(name) > 0; }
  const std::map<std::string, ParamValue>& values() const { return values_; }
  nlohmann::json to_json() const;
  // to_json without the knobs of `specs` that are not keyed at their default and hold it: what a run
  // key hashes.
  nlohmann::json key_json(const std::vector<ParamSpec>& specs) const;

 private:
  const ParamValue& get(const std::string& name) const;
  std::map<std::string, ParamValue> values_;
};

class ParamDict {
 public:
  struct Entry {
    std::string text;
    SourceLocation where;
  };

  void set(const std::string& key, const std::string& text, const SourceLocation& where);
  // "key=value" from the command line.
  void set_assignment(const std::string& assignment, const std::string& origin);
  // Every key of a YAML map.
  void set_from_config(const ConfigNode& map);
  bool empty() const { return entries_.empty(); }
  const std::map<std::string, Entry>& entries() const { return entries_; }

  // Checks every entry against the specs (unknown key, type, range, a knob set where it does not
  // apply) and fills in the defaults of the knobs that apply. `owner` names the method in messages.
  // Entries named in `droppable` (knobs a sweep varies) are dropped silently where they do not apply.
  ParamSet resolve(const std::vector<ParamSpec>& specs, const std::string& owner,
                   const std::set<std::string>& droppable = {}) const;

 private:
  std::map<std::string, Entry> entries_;
};

// The subset of a ParamSet whose specs have the given phase.
ParamSet select_phase(const ParamSet& all, const std::vector<ParamSpec>& specs, ParamPhase phase);

}  // namespace causticbench
