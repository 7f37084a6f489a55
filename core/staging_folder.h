// A folder filled under a temporary name next to its final path and renamed into place, so that a
// reader never sees it half written and a process killed mid-way leaves only a staging folder that
// remove_stale_staging() cleans up. Used for run folders (store/result_paths.h) and builds
// (store/build_cache.h).
//
// Replacing an existing folder (a --force rerun) is one atomic exchange of the two names
// (renameat2 RENAME_EXCHANGE), after which the old copy sits under the staging name and is removed: a
// kill at any moment leaves the old copy or the new one in place, never neither. Where the file system
// cannot exchange, the old copy is first renamed to <staging>.old and the new one then renamed into
// place; remove_stale_staging() finishes such a replacement that a kill interrupted (the staging
// folder is complete once its .old exists) or puts the old copy back. Each commit step is a write step
// of core/files.h's fault injection: "commit FINAL", "replace FINAL" (between the two renames),
// "discard OLD" (before the old copy is removed).
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
  // Replaces any existing final folder (a --force rerun, a damaged copy) and renames the staging folder
  // into place. WriteError (core/files.h) when it cannot; the old copy is then still in place.
  void commit();
  // Renames the staging folder into place unless the final folder exists (another process finished
  // the same content first: its copy wins and ours is removed). Returns whether ours was used.
  bool commit_if_absent();

 private:
  std::string final_, staging_;
  bool committed_ = false;
};

// In `folder`: finishes or undoes the replacements that processes of this host were killed in (see
// above), then removes their staging folders.
void remove_stale_staging(const std::string& folder);

}  // namespace causticbench
