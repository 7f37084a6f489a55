// A method's knobs and capabilities as text: `causticbench describe` prints them, and the block
// `describe --markdown` prints opens the method's README (the conformance tests check that it does).
#pragma once

#include <string>

#include "methods/method.h"

namespace causticbench {

std::string describe_markdown(const MethodInfo& info);
std::string describe_text(const MethodInfo& info);

}  // namespace causticbench
