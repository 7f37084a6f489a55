// external's `command`: a shell command line with placeholders in braces, filled in per frame. Each value
// is given in a shell variable assigned before the command, and the placeholder becomes a reference to
// it, so that a path with spaces or quotes reaches the program as one word and no value is run; `{{` and
// `}}` are literal braces. See methods/external/README.md for the placeholders.
#pragma once

#include <map>
#include <string>

#include "methods/param_dict.h"

namespace causticbench {

// The placeholders every frame fills in, with what each holds (for messages and the README).
const std::map<std::string, std::string>& command_placeholders();

// The shell variable a placeholder's value is given in: CAUSTICBENCH_OUT for {out},
// CAUSTICBENCH_PROGRAM_PHOTONS for {program.photons}.
std::string placeholder_variable(const std::string& name);

// What /bin/sh -c runs for `command`: a line `export CAUSTICBENCH_NAME='value'` (shell-quoted) for each
// placeholder used, then the command with each {name} replaced by a reference to that variable ("${...}"
// outside quotes, bare inside double quotes), so that no value is ever parsed by the shell as code.
// Throws std::invalid_argument naming the first placeholder that `values` lacks, a placeholder inside
// single quotes or after '$' or a backslash, a quote never closed, or a brace without its partner.
std::string expand_command(const std::string& command, const std::map<std::string, std::string>& values);

// The program knobs of a resolved knob set ("program.photons" -> "100000"), as the command receives them.
std::map<std::string, std::string> program_knobs(const ParamSet& knobs);

// "" when `command` is one that expand_command can fill with the frame's placeholders and `knobs` (the
// names of the program knobs set, "program.photons"); otherwise what is wrong and what is known.
std::string command_problem(const std::string& command, const std::map<std::string, std::string>& knobs);

}  // namespace causticbench
