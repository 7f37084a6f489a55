// Where results live and how they are written: every run and reference frame appears complete or not
// at all (written into a staging folder or temporary file, then renamed), so a sweep killed at any
// moment resumes with nothing lost and nothing duplicated. Layout: docs/results-format.md.
#pragma once

#include <string>

namespace causticbench {

struct ResultPaths {
  std::string results;  // the results root, e.g. "results"

  std::string experiment(const std::string& name) const;
  std::string run(const std::string& experiment_name, const std::string& key) const;
  std::string reference(const std::string& key) const;
  static std::string frame_file(int frame, const std::string& prefix = "frame");
};

bool run_is_stored(const std::string& run_folder);

// A folder filled under a temporary name next to its final path and renamed into place by commit().
// Destroyed without commit, it removes itself.
class StagingFolder {
 public:
  explicit StagingFolder(std::string final_path);
  ~StagingFolder();
  StagingFolder(const StagingFolder&) = delete;
  StagingFolder& operator=(const StagingFolder&) = delete;
  const std::string& path() const { return staging_; }
  // Replaces any existing final folder (a --force rerun) and renames the staging folder into place.
  void commit();

 private:
  std::string final_, staging_;
  bool committed_ = false;
};

// Removes staging folders left by runners of this host that no longer exist (killed mid-run).
void remove_stale_staging(const std::string& folder);

}  // namespace causticbench
