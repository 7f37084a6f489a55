// The result store of one experiment: per run, what is stored (absent, current, damaged, or stored but
// due again: measured against another copy of its reference, against a reference of other scene content,
// or against another reference than its variant's now: stale); the claim of a run under its lock; and the
// put of its outcome. The runner asks it once per phase (selection, after the references, claim, put),
// and `causticbench status` judges staleness by the same rule (measured_against_other_reference).
// Files, locks and layout: store/run_folders.h, store/store_lock.h, docs/results-format.md.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/result_paths.h"
#include "store/run_folders.h"
#include "store/store_lock.h"

namespace causticbench {

// One run as the store knows it: its key and label, and its variant's reference now.
struct RunAddress {
  std::string key, label;
  std::string reference_key;  // the variant's current reference
  std::string content_hash;   // the variant's scene content now (a mesh edited in place changes it)
  int seeds = 1;              // the seeds it is to be measured with (experiments/seed_replicas.h)
};

struct RunState {
  enum class Kind {
    absent,         // nothing stored
    current,        // stored, measured against the variant's reference as stored (or not yet stored)
    damaged,        // a folder whose record fails its checks (store/record_check.h)
    other_copy,     // measured against another copy of its reference than the stored one
    other_content,  // its reference was computed for other scene content
    stale,          // measured against another reference than its variant's now
    fewer_seeds,    // measured with fewer seeds than the experiment asks for now
  };
  Kind kind = Kind::absent;
  std::string problem;      // damaged: "<folder>/record.json: <what is wrong>"
  nlohmann::json record;    // stored kinds: the record
  std::string record_hash;  // stored kinds: xxHash64 of record.json (tells whether another process replaced it)
  // current: whether its reference's stored checksums were there to compare with; a run whose reference
  // was not stored is looked up again once the references are (ResultStore::references_changed).
  bool reference_checked = false;

  bool stored() const { return kind != Kind::absent && kind != Kind::damaged; }
  // Whether `run` has to measure it (force: every selected run).
  bool to_run(bool force) const { return force || kind != Kind::current; }
};

// A run this process holds the lock of, and may put.
struct RunClaim {
  RunAddress run;
  StoreLock lock;
};

class ResultStore {
 public:
  ResultStore(ResultPaths paths, std::string experiment, std::vector<int> frames);
  const ResultPaths& paths() const { return paths_; }

  // What is stored for the run. With `warn`, a stored copy that is due again says why on stderr.
  RunState look_up(const RunAddress& run, bool warn = true);
  // The references were computed or loaded since the last look-up: their stored checksums are read again.
  void references_changed();

  // The run's lock if no other process holds it, and the run still to do once looked at again under it:
  // not stored, or still the copy `seen` that this process means to replace (`replace`). `held` says
  // whether another process held the lock (the caller waits for it later); otherwise std::nullopt means
  // another process stored the run meanwhile.
  std::optional<RunClaim> try_claim(const RunAddress& run, const RunState& seen, bool replace, bool& held);
  // The same, waiting for the lock.
  std::optional<RunClaim> claim(const RunAddress& run, const RunState& seen, bool replace);
  // Writes the claimed run's folder: images (file name, EXR bytes), then its record (store/run_folders.h).
  void put(const RunClaim& claim, const std::vector<std::pair<std::string, std::string>>& images,
           nlohmann::json record);

 private:
  std::optional<RunClaim> still_to_run(const RunAddress& run, const RunState& seen, bool replace, StoreLock lock);
  const std::optional<nlohmann::json>& reference_checksums(const std::string& reference_key);
  bool reference_content_differs(const RunAddress& run);

  ResultPaths paths_;
  std::string experiment_;
  std::vector<int> frames_;
  std::map<std::string, std::optional<nlohmann::json>> checksums_;     // reference key -> its stored images' checksums
  std::map<std::string, bool> content_differs_;                        // reference key + content -> differs
};

}  // namespace causticbench
