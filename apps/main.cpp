// causticbench: real-time caustics methods behind one interface, measured against a converged reference.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "apps/commands.h"
#include "core/errors.h"
#include "core/progress.h"

int main(int argc, char** argv) {
  using namespace causticbench;
  CLI::App app{
      "causticbench: caustics rendering methods from the literature behind one interface, each measured against a\n"
      "converged reference. Every method writes caustic irradiance E_c (W/m^2, RGB) at the same G-buffer points.\n"
      "Exit codes: 0 success, 1 internal failure, 2 bad input (scene, knob, command line), nothing written."};
  app.require_subcommand(1);
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "no progress lines");

  RenderOptions render;
  CLI::App* render_command = app.add_subcommand(
      "render", "Render one frame of a scene with one method; writes caustic.exr (E_c), direct.exr, gbuffer.exr,\n"
                "composite.png, caustic.png and record.json (settings, timings, counters) into --out.");
  render_command->add_option("scene", render.scene, "scene file (YAML, see docs/scene-format.md)")->required();
  render_command->add_option("-m,--method", render.method, "method name (see `causticbench list`)")->capture_default_str();
  render_command->add_option("-s,--set", render.assignments, "knob=value, repeatable (see `causticbench describe METHOD`)");
  render_command->add_option("-o,--out", render.out, "output folder")->required();
  render_command->add_option("-f,--frame", render.frame, "frame index of an animated scene")->capture_default_str();
  render_command->add_option("-t,--threads", render.threads, "worker threads (0: all cores)")->capture_default_str();
  render_command->add_option("-r,--resolution", render.resolution, "override the camera resolution, WIDTHxHEIGHT");
  render_command->add_option("--direct-samples", render.direct_samples, "light samples per pixel for direct.exr")
      ->capture_default_str()->check(CLI::Range(1, 4096));

  CLI::App* list_command = app.add_subcommand("list", "List the methods and their capability matrix.");
  std::string describe_name;
  bool markdown = false;
  CLI::App* describe_command = app.add_subcommand("describe", "Print a method's knobs (name, phase, type, default, range, meaning).");
  describe_command->add_option("method", describe_name, "method name")->required();
  describe_command->add_flag("--markdown", markdown, "print the table as Markdown (the method's README table)");
  std::string validate_file;
  CLI::App* validate_command = app.add_subcommand("validate", "Check a scene file; the first defect is reported with file, line, column, key, expected and found.");
  validate_command->add_option("file", validate_file, "scene file")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    int code = app.exit(error);
    return code == 0 ? 0 : 2;
  }
  Progress::set_quiet(quiet);
  try {
    if (*render_command) return run_render(render);
    if (*list_command) return run_list();
    if (*describe_command) return run_describe(describe_name, markdown);
    if (*validate_command) return run_validate(validate_file);
  } catch (const InputError& error) {
    fmt::print(stderr, "error: {}\n", error.what());
    return 2;
  } catch (const std::exception& error) {
    fmt::print(stderr, "internal error: {}\n", error.what());
    return 1;
  }
  return 0;
}
