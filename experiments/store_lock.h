// Exclusive locks of the results store: one per reference key and one per run key, so that processes
// sharing a results folder (two `causticbench run` of one experiment, the shards of a sweep) never
// compute the same reference or run twice. A lock is flock(2) on a file under <results>/.locks/
// (ResultPaths): the kernel releases it when its holder exits, killed or not, so a dead process never
// leaves a lock behind. The file holds "pid <pid> on <host>" of the holder, for the waiting message only.
#pragma once

#include <optional>
#include <string>

namespace causticbench {

class StoreLock {
 public:
  // The lock if no other process holds it, std::nullopt otherwise; WriteError when the lock file cannot
  // be created.
  static std::optional<StoreLock> try_acquire(const std::string& path);
  // The lock, waiting for its holder when there is one; before waiting, says once on stderr
  // "waiting for <what>: pid N on HOST holds it (lock PATH)".
  static StoreLock acquire(const std::string& path, const std::string& what);

  StoreLock(StoreLock&& other) noexcept;
  StoreLock& operator=(StoreLock&& other) noexcept;
  StoreLock(const StoreLock&) = delete;
  StoreLock& operator=(const StoreLock&) = delete;
  ~StoreLock();

 private:
  explicit StoreLock(int descriptor);
  void release();
  int descriptor_ = -1;
};

}  // namespace causticbench
