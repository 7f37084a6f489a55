// Exclusive locks of the results store: one per reference key and one per run key, so that processes
// sharing a results folder (two `causticbench run` of one experiment, the shards of a sweep on a cluster)
// never compute the same reference or run twice. The folder may be NFS as clusters mount it, where
// flock(2) is missing or only local to one client, so a lock is the existence of a file
// <results>/.locks/.../<key>.lock (ResultPaths), created by link(2) of a complete temporary file: atomic
// on every NFS version, and the file never exists without its holder line
// "pid <pid> on <host> started <start> token <random>".
//
// A holder that dies leaves its file behind; the next process that wants the lock removes it when it is
// stale:
//  - held on this host by a process that no longer exists (the pid is gone, or now belongs to a process
//    that started at another time): at once;
//  - held on another host: when its heartbeat stopped. A holder refreshes the modification time of every
//    lock it holds every stale/8 seconds (one thread per process), and a lock not refreshed for
//    CAUSTICBENCH_LOCK_STALE_SECONDS (default 120) is stale. The age is measured against the
//    modification time of a file just touched in the same folder, so the file server's clock is the only
//    clock involved and skewed clocks on the nodes do not matter.
// Removing a stale lock is itself done under <lock>.break (created the same way), after reading the lock
// again: two processes that find the same stale lock never remove a fresh one another just took.
#pragma once

#include <optional>
#include <string>

namespace causticbench {

class StoreLock {
 public:
  // The lock if no other live process holds it (a stale one is removed first, with a warning on
  // stderr), std::nullopt otherwise; WriteError when the lock file cannot be created.
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
  StoreLock(std::string path, std::string holder);
  void release();
  std::string path_;    // empty when moved from or released
  std::string holder_;  // the line this process wrote: the lock is removed only while it still holds it
};

// Seconds without a heartbeat after which a lock held on another host is stale
// (CAUSTICBENCH_LOCK_STALE_SECONDS, default 120).
double lock_stale_seconds();

}  // namespace causticbench
