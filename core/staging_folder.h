// A folder filled under a temporary name next to its final path and renamed into place, so that a
// reader never sees it half written and a process killed mid-way leaves only a staging folder that
// remove_stale_staging() cleans up. Used for run folders (experiments/result_store.h) and builds
// (methods/build_cache.h).
#pragma once

#include <string>

namespace causticbench {

class StagingFolder {
 public:
  explicit StagingFolder(std::string final_path);
  ~StagingFolder();
  StagingFolder(const StagingFolder&) = delete;
  StagingFolder& operator=(const StagingFolder&) = delete;
  const std::string& path() const { return staging_; }
  // Replaces any existing final folder (a --force rerun) and renames the staging folder into place.
  void commit();
  // Renames the staging folder into place unless the final folder exists (another process finished
  // the same content first: its copy wins and ours is removed). Returns whether ours was used.
  bool commit_if_absent();

 private:
  std::string final_, staging_;
  bool committed_ = false;
};

// Removes staging folders left by processes of this host that no longer exist (killed mid-run).
void remove_stale_staging(const std::string& folder);

}  // namespace causticbench
