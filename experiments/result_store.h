// Where results live and how they are written: every run and reference frame appears complete or not
// at all (written into a staging folder or temporary file, then renamed), so a sweep killed at any
// moment resumes with nothing lost and nothing duplicated. Layout: docs/results-format.md.
#pragma once

#include <string>

#include "core/staging_folder.h"

namespace causticbench {

struct ResultPaths {
  std::string results;  // the results root, e.g. "results"

  std::string experiment(const std::string& name) const;
  std::string run(const std::string& experiment_name, const std::string& key) const;
  std::string reference(const std::string& key) const;
  std::string builds() const;  // the build cache: <results>/builds/<key>/ (methods/build_cache.h)
  static std::string frame_file(int frame, const std::string& prefix = "frame");
};

bool run_is_stored(const std::string& run_folder);

}  // namespace causticbench
