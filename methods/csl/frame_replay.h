// The csl method's entry in methods/frame_dumps.cpp: reads a `--dump-frame` folder that
// CslMethod::dump_frame wrote (methods/csl/frame_data.h) and replays it with VulkanCsl. Depends only on
// gpu/ and the standard library, like the rest of causticbench-gpubench.
#pragma once

#include "methods/frame_dump.h"

namespace causticbench {

FrameDumpFormat csl_frame_dump_format();

}  // namespace causticbench
