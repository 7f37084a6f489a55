// Atomic file output, the one way the results store writes a file (docs/results-format.md,
// "Guarantees"): the payload goes to a temporary name in the same folder,
// `<name>.partial.<host>-<pid>.<n><extension>`, is flushed to disk, and is renamed over its final name,
// so that a reader (or a resumed run) sees the old file or the new one, never half of one. On any
// failure the temporary file is removed and a WriteError names the final path and the OS error by name
// ("No space left on device (ENOSPC)"). Temporary files of processes that died before they could clean
// up are removed by remove_stale_partial_files() on the next run.
//
// Fault injection, for the tests of those guarantees (tests/test_reliability_store.cpp): every write
// step (writing a temporary file, renaming it into place, and the commit steps of a staging folder,
// core/staging_folder.h) is numbered from 1 in each process, and CAUSTICBENCH_FAULT_INJECT makes chosen
// steps fail or kill the process. It is a comma-separated list of
//   kill@N      SIGKILL at step N (a write step first writes half its temporary file)
//   fail@N      step N fails as a full disk would (ENOSPC; EIO for renames), after half a write
//   kill@TEXT   (and fail@TEXT) every step whose description contains TEXT, e.g. fail@record.json
//   trace       print every step to stderr: "fault injection: step 3: write results/x/environment.json"
//   no_rename_exchange   commit staging folders by two renames instead of one atomic exchange
// Unset (the normal case) it costs one getenv per write.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace causticbench {

// A file of the store could not be written: the message names the file and the OS error.
class WriteError : public std::runtime_error {
 public:
  explicit WriteError(const std::string& message) : std::runtime_error(message) {}
};

// "No space left on device (ENOSPC)": the system's text and the error's symbolic name.
std::string os_error_text(int error_number);

// Writes `bytes` (text or binary) to `path` atomically; WriteError on failure, with nothing left behind.
void write_file_atomically(const std::string& path, std::string_view bytes);
void write_text_atomically(const std::string& path, const std::string& text);
// For writers that can only write to a path (image libraries): `writer` writes the file at the temporary
// path it is given, which keeps `path`'s extension; the file is then renamed into place. Whatever the
// writer leaves under the temporary name (its own temporaries included) is removed if anything fails.
void write_file_atomically_with(const std::string& path, const std::function<void(const std::string& temporary)>& writer);
// For writers that stream (a method's build files): `writer` writes into a binary stream on the temporary
// file; a stream that fails (a full disk) is a WriteError naming the file and the OS error, and nothing
// is left behind.
void write_stream_atomically(const std::string& path, const std::function<void(std::ostream& stream)>& writer);
// Creates a folder of the store and its parents; WriteError naming the OS error when it cannot.
void make_folders(const std::string& path);
// Renames `from` over `to` as one write step (fault injection included); WriteError naming both.
void rename_atomically(const std::string& from, const std::string& to);

// Removes, in `folder` (not below it), the temporary files of write_file_atomically left by processes of
// this host that no longer exist; with `folder_is_locked` (the caller holds the folder's lock, so no
// other writer is at work in it) also those that carry no process id (written by older versions).
// Returns how many were removed.
size_t remove_stale_partial_files(const std::string& folder, bool folder_is_locked = false);
// Whether `name` is the name of such a temporary file.
bool is_partial_file_name(const std::string& name);

// This machine's name and whether process `pid` of it still exists: what the stale-file cleanups of
// this file and core/staging_folder.h decide with.
std::string host_name();
bool process_exists(int pid);

// Fault injection (see above). Every write step of the store calls next_write_step() once with what it
// is about to do ("write PATH", "rename PATH", "commit FOLDER", ...) and acts on the answer.
enum class InjectedFault { none, fail, kill };
InjectedFault next_write_step(const std::string& description);
// SIGKILL to this process: no destructor, no flush, as a real kill.
[[noreturn]] void kill_this_process();
// Whether CAUSTICBENCH_FAULT_INJECT holds `option` (e.g. "no_rename_exchange").
bool fault_injection_option(const std::string& option);

// The largest scene or experiment file read_text() accepts. A YAML node costs a few hundred bytes in
// memory, so this bounds what parsing can take (to about 1 GB) and keeps a mistaken file (a log, a
// 50 MB list) from exhausting memory before any check can run.
constexpr uintmax_t kMaximumConfigurationBytes = 4u << 20;
// The whole text of a configuration file; InputError naming it when it does not exist, is not a regular
// file (a FIFO, a device, a folder), is larger than `most_bytes` or cannot be read. `kind` says what the
// file was expected to be, for those messages ("a scene or experiment", "a statistics file (JSON)").
std::string read_text(const std::string& path, const std::string& kind = "a scene or experiment",
                      uintmax_t most_bytes = kMaximumConfigurationBytes);
// Creates the folder (and parents); throws InputError if it exists as a file or cannot be created.
void ensure_folder(const std::string& path);

}  // namespace causticbench
