// Where results live: the results folder's layout (docs/results-format.md), and the check, before any
// work, that a folder an option names can be written.
#pragma once

#include <string>

namespace causticbench {

// --results names a folder this process can write, or one it can create: checked before any work, so
// that a file of that name, a symbolic-link loop or a read-only parent is an input error (exit code 2)
// naming the path and the system's reason, not an internal error after the reference was computed.
void check_results_folder(const std::string& path);
// The same check for any folder an option names (`option` and `what` in the message): a writable folder, or
// one that can be made below a writable one; InputError (exit 2) otherwise.
void check_writable_folder(const std::string& option, const std::string& what, const std::string& path);
// For a folder that is no experiment's results folder (no experiment.json): "; the experiment folders
// inside it are: results/a, results/b" when it holds some (a results folder given for an experiment's),
// else "; `causticbench run EXPERIMENT.yaml` writes one as results/<experiment>/". `given` as the user
// typed it, so that the paths shown can be copied.
std::string experiment_folders_hint(const std::string& given);

struct ResultPaths {
  std::string results;  // the results root, e.g. "results"

  std::string experiment(const std::string& name) const;
  std::string run(const std::string& experiment_name, const std::string& key) const;
  std::string reference(const std::string& key) const;
  std::string builds() const;  // the build cache: <results>/builds/<key>/ (store/build_cache.h)
  // Lock files: <results>/.locks/references/<key>.lock and <results>/.locks/runs/<experiment>/<key>.lock
  // (a hidden folder, which no experiment name can be).
  std::string reference_lock(const std::string& key) const;
  std::string run_lock(const std::string& experiment_name, const std::string& key) const;
  static std::string frame_file(int frame, const std::string& prefix = "frame");
};

}  // namespace causticbench
