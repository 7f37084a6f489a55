// The pinhole method's entry in methods/frame_dumps.cpp: reads a `--dump-frame` folder that
// PinholeMethod::dump_frame wrote (methods/pinhole/frame_data.h) and replays it with VulkanPinhole.
// Depends only on gpu/ and the standard library, like the rest of causticbench-gpubench.
#pragma once

#include "methods/frame_dump.h"

namespace causticbench {

FrameDumpFormat pinhole_frame_dump_format();

}  // namespace causticbench
