// The report's "Capability matrix" (docs/reports.md): for an experiment that declares
// `capability_matrix`, one row per capability case and, per method, the published mark (a paper's table),
// the declared capability (stored in experiment.json), the measured verdict on the case's variant by the
// shared rule (experiments/capability_verdict.h), the error there and on the twin without the
// difficulty, and a flag with a one-line reason wherever the three disagree. Built from plain inputs so
// that tests can feed it synthetic records; the writers take those inputs from the Report.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/capability_verdict.h"

namespace causticbench {

// One stored run as the matrix needs it.
struct CapabilityRun {
  std::string method, variant, label;
  nlohmann::json knobs = nlohmann::json::object();  // as --filter sees them (record_knobs)
  bool failed = false;                               // status not ok: refused, unless nonfinite
  bool nonfinite = false;                            // failed on non-finite pixels: wrong, not refused
  std::string error;
  std::optional<double> energy_ratio, relmse;
};

// One method on one variant of a case.
struct CapabilityMeasurement {
  bool found = false;  // a run was selected (false: not run yet, or the selection matches none)
  CapabilityVerdict verdict = CapabilityVerdict::neither;
  std::optional<double> energy_ratio, relmse;
  std::string error;   // the refusal's message
};

struct CapabilityCell {
  std::string method;
  std::optional<bool> published;  // none: the table has no row for the capability or no column for the method
  std::optional<bool> declared;   // none: experiment.json has no declaration of the method
  std::string note;               // the method's capability note, if any
  CapabilityMeasurement with, without;
  bool judged = true;             // false: the case is built on a capability the method declares false
  std::vector<std::string> flags;  // one line per disagreement
};

struct CapabilityRow {
  std::string capability, with, without, built_on;
  std::vector<std::string> table_rows;  // the published table's rows mapped to this capability
  std::vector<CapabilityCell> cells;    // one per method, in `methods` order
};

struct CapabilityMatrix {
  std::string title;                 // the published table's, or empty
  std::vector<std::string> methods;  // declared methods, in experiment.json order
  std::vector<CapabilityRow> rows;
  std::vector<std::string> notes;    // references too noisy to judge by
};

// `settings`: experiment.json "capability_matrix"; `reference_errors`: each variant's reference error.
CapabilityMatrix build_capability_matrix(const nlohmann::json& settings, const std::vector<CapabilityRun>& runs,
                                         const std::map<std::string, double>& reference_errors);

// The section with its heading (the study's summary names the experiment in it).
std::string capability_matrix_markdown(const CapabilityMatrix& matrix, const std::string& heading = "Capability matrix");
std::string capability_matrix_html(const CapabilityMatrix& matrix, const std::string& heading = "Capability matrix");
nlohmann::json capability_matrix_json(const CapabilityMatrix& matrix);

namespace report_detail {
struct Report;
// The matrix of a loaded report; none when its experiment declares no capability matrix.
std::optional<CapabilityMatrix> report_capability_matrix(const Report& report);
}  // namespace report_detail

}  // namespace causticbench
