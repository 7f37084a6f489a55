// The lpi method's entry in methods/frame_dumps.cpp: reads a `--dump-frame` folder that
// LpiMethod::dump_frame wrote (methods/lpi/frame_data.h) and replays it with VulkanLpi. Depends only
// on gpu/ and the standard library, like the rest of causticbench-gpubench.
#pragma once

#include "methods/frame_dump.h"

namespace causticbench {

FrameDumpFormat lpi_frame_dump_format();

}  // namespace causticbench
