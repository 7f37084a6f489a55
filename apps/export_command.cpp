// `causticbench export SCENE --out DIR`: one frame's files as the `external` method hands them to its
// program (core/scene_export.h: scene.json, world.json, meshes, environment maps) with the frame's
// G-buffer, so that a program can be written and debugged against them before any sweep runs it.
#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "apps/commands.h"
#include "core/files.h"
#include "core/scene_export.h"
#include "methods/lifecycle.h"
#include "store/result_paths.h"

namespace causticbench {

int run_export(const ExportOptions& options) {
  // Everything is checked before any file is written.
  const Scene scene = load_scene_at_resolution(options.scene, options.resolution);
  if (options.frame < 0 || options.frame >= scene.frames) {
    throw InputError(fmt::format("--frame: expected 0 to {} ({} frames in {}), found {}", scene.frames - 1, scene.frames,
                                 scene.source, options.frame));
  }
  check_writable_folder("--out", "the frame's files", options.out);
  make_folders(options.out);
  const PosedFrame posed(scene, options.frame);
  SceneExporter exporter(options.out);
  exporter.write(posed.frame);
  write_exr(posed.gbuffer.to_image(), options.out + "/gbuffer.exr", GBuffer::channel_names());
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(options.out)) files.push_back(entry.path().filename().string());
  std::sort(files.begin(), files.end());
  fmt::print("wrote frame {} of {} into {}: {}\n", options.frame, options.scene, options.out, join(files, ", "));
  return 0;
}

}  // namespace causticbench
