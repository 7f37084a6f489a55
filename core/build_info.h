// What the running binary was built from, for the environment block of records and reports.
#pragma once

namespace causticbench {

// The short git revision of the checkout this binary was built from, with "-dirty" when tracked files
// had uncommitted changes, or "unknown" outside a git checkout. Taken at build time, not configure time.
const char* git_revision();

}  // namespace causticbench
