// The one file that includes the generated revision header, so that a new commit recompiles only this file.
#include "core/build_info.h"

#include "git_revision.h"

namespace causticbench {

const char* git_revision() { return CAUSTICBENCH_GIT_REVISION; }

}  // namespace causticbench
