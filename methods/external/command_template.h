// external's `command`: a shell command line with placeholders in braces, filled in per frame. Each value
// is shell-quoted, so that paths with spaces or quotes reach the program as one word; `{{` and `}}` are
// literal braces. See methods/external/README.md for the placeholders.
#pragma once

#include <map>
#include <string>

#include "methods/param_dict.h"

namespace causticbench {

// The placeholders every frame fills in, with what each holds (for messages and the README).
const std::map<std::string, std::string>& command_placeholders();

// The command with every {name} replaced by values.at(name), shell-quoted. Throws std::invalid_argument
// naming the first placeholder that `values` lacks, or a brace without its partner.
std::string expand_command(const std::string& command, const std::map<std::string, std::string>& values);

// The program knobs of a resolved knob set ("program.photons" -> "100000"), as the command receives them.
std::map<std::string, std::string> program_knobs(const ParamSet& knobs);

// "" when `command` is one that expand_command can fill with the frame's placeholders and `knobs` (the
// names of the program knobs set, "program.photons"); otherwise what is wrong and what is known.
std::string command_problem(const std::string& command, const std::map<std::string, std::string>& knobs);

}  // namespace causticbench
