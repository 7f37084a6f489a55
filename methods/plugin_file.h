// Whether a file can be handed to dlopen() without taking the process down: dlopen maps a library's
// segments where its program headers say they are, and touching a page past the end of a truncated file
// is SIGBUS, not an error it could return. So the file is read against its own headers first.
#pragma once

#include <string>

namespace causticbench {

// "" when `path` is a whole 64-bit ELF shared object for this machine whose program and section headers,
// and every segment they name, lie inside the file; otherwise what is wrong ("it is 4096 bytes, but its
// segment 2 ends at byte 20480: the file is truncated").
std::string plugin_file_problem(const std::string& path);

}  // namespace causticbench
