// An experiment's `capability_matrix` key (docs/experiment-format.md, "Capability matrix"): the published
// matrix (a paper's table of which method models what), the cases (a capability, the variant that needs
// it and its twin without the difficulty), which run of a method a case is judged by, and, filled in
// from the method registry when the experiment is read, each method's declared capabilities: the report
// reads only stored files, so the declarations travel in experiment.json beside the runs they judge.
#pragma once

#include <nlohmann/json.hpp>

namespace causticbench {

class ConfigNode;
struct Experiment;

// Reads and checks `node` against the expanded experiment (its variants, methods and runs): every
// capability, method and variant it names must exist, and every case must select exactly one run of each
// method on each of its two variants. Returns the canonical JSON stored in experiment.json:
//   {published: {title, rows: {capability: [row, ...]}, methods: {method: [capability, ...]}} or null,
//    frame: the frame judged (`frame`, default the experiment's last),
//    select: {method: filter}, cases: [{capability, with, without, built_on, select: {method: filter}}],
//    declared: {method: {capabilities: {capability: bool}, notes: {capability: text}}}}
// Every defect is an InputError with file, line and key.
nlohmann::json read_capability_matrix(const ConfigNode& node, const Experiment& experiment);

}  // namespace causticbench
