// Atomic file output: write to a temporary name in the same folder, then rename, so that a reader
// (or a resumed run) never sees a half-written file.
#pragma once

#include <string>

namespace causticbench {

void write_text_atomically(const std::string& path, const std::string& text);
// The whole file; InputError naming it when it does not exist or cannot be read.
std::string read_text(const std::string& path);
// Creates the folder (and parents); throws InputError if it exists as a file or cannot be created.
void ensure_folder(const std::string& path);

}  // namespace causticbench
