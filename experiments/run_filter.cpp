// --filter and the claims' run selections over an experiment's runs and over stored records
// (declared in experiment.h): matching terms, and refusing terms that could match no run.
#include <algorithm>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "core/errors.h"
#include "experiments/experiment.h"
#include "store/run_record.h"

namespace causticbench {

bool matches_filter(const std::string& method, const std::string& label, const nlohmann::json& knobs,
                    const std::string& filter) {
  std::stringstream terms(filter);
  for (std::string term; std::getline(terms, term, ',');) {
    if (term.empty()) continue;
    size_t equals = term.find('=');
    if (equals == std::string::npos) {
      if (label.find(term) == std::string::npos) return false;
      continue;
    }
    std::string name = term.substr(0, equals), value = term.substr(equals + 1);
    if (name == "method") {
      if (method != value) return false;
      continue;
    }
    if (!knobs.is_object() || !knobs.contains(name)) return false;
    const nlohmann::json& actual = knobs.at(name);
    double wanted = 0.0;
    if (actual.is_number() && (std::stringstream(value) >> wanted)) {
      if (actual.get<double>() != wanted) return false;
    } else {
      std::string text = actual.is_string() ? actual.get<std::string>() : actual.dump();
      if (text != value) return false;
    }
  }
  return true;
}

bool run_matches_filter(const Experiment& experiment, const RunSpec& run, const std::string& filter) {
  nlohmann::json knobs = run.params.to_json();
  knobs["variant"] = experiment.variants.at(run.variant).name;
  return matches_filter(run.method, run.label, knobs, filter);
}

namespace {

// Throws when `value` is none of `allowed`; `what` names the set ("knob", "method", "variant").
void check_filter_word(const std::string& term, const std::string& value, const std::vector<std::string>& allowed,
                       const std::string& what) {
  if (std::find(allowed.begin(), allowed.end(), value) != allowed.end()) return;
  std::string expected =
      fmt::format("a {} of the experiment: {}{}", what, join(allowed, ", "), did_you_mean(value, allowed));
  throw_input_error(SourceLocation{"--filter"}, term, expected, "'" + value + "'");
}

}  // namespace

void check_filter_terms(const Experiment& experiment, const std::string& filter) {
  std::set<std::string> methods, knobs = {"method", "variant"};
  for (const RunSpec& run : experiment.runs) {
    // A family's members (external's program.*) are known by the runs that set them.
    for (const auto& [name, value] : run.params.values()) knobs.insert(name);
    if (!methods.insert(run.method).second) continue;
    for (const ParamSpec& spec : find_method(run.method).info().params)
      if (!spec.family) knobs.insert(spec.name);
  }
  std::vector<std::string> variants;
  for (const SceneVariant& variant : experiment.variants) variants.push_back(variant.name);
  std::stringstream terms(filter);
  for (std::string term; std::getline(terms, term, ',');) {
    size_t equals = term.find('=');
    if (equals == std::string::npos) continue;
    std::string name = term.substr(0, equals), value = term.substr(equals + 1);
    check_filter_word(term, name, {knobs.begin(), knobs.end()}, "knob");
    if (name == "method") check_filter_word(term, value, {methods.begin(), methods.end()}, "method");
    if (name == "variant") check_filter_word(term, value, variants, "variant");
  }
}

nlohmann::json record_knobs(const nlohmann::json& record) {
  nlohmann::json knobs = nlohmann::json::object();
  for (const char* phase : {"build", "frame", "render"}) {
    if (record.contains(phase) && record[phase].is_object()) knobs.update(record[phase]);
  }
  for (const char* field : {"variant", "receiver_pixels"}) {
    if (record.contains(field)) knobs[field] = record[field];
  }
  return knobs;
}

bool record_matches_filter(const nlohmann::json& record, const std::string& filter) {
  return matches_filter(record.value("method", ""), record.value("label", ""), record_knobs(record), filter);
}

bool record_matches_filter(const RunRecord& record, const std::string& filter) {
  return matches_filter(record.method, record.label, record.knobs(), filter);
}

}  // namespace causticbench
