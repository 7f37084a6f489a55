// external's declarations: its knobs, capabilities and counters (README.md's table is generated from them).
#include "methods/external/command_template.h"
#include "methods/external/external.h"

namespace causticbench {

const MethodInfo& ExternalMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "external";
    m.paper = "none: your program (methods/external/README.md says what it is given and what it returns)";
    m.summary = "Runs a program of your own once per frame on the frame's scene (a causticbench scene file, the frame in "
                "world space, meshes and environment maps as files) and G-buffer (EXR), and measures the E_c image it "
                "writes like any method's.";
    // Build knobs, all of them: each run is then prepared on its own, so that one setting's failure, even a
    // hang, fails that run alone (runs differing only in render knobs share one pass over the frames).
    m.params = {
        ParamSpec::text("command", "",
                        "the shell command run for each frame (/bin/sh -c), with placeholders {scene}, {world}, {gbuffer}, "
                        "{out}, {stats}, {folder}, {frame}, {width}, {height}, {causticbench} and {program.NAME}, each "
                        "standing for its value (a shell variable, never parsed as code; not inside single quotes); "
                        "{{ and }} are braces",
                        ParamPhase::build),
        ParamSpec::real("timeout_seconds", 600.0, 0.001, 1e6,
                        "how long one frame's program may run before it is killed (with everything it started) and its "
                        "run fails",
                        ParamPhase::build),
        ParamSpec::family_of("program.",
                             "a knob of your program, passed through: {program.NAME} in the command, and part of the run "
                             "key like any knob (sweep it, filter by it, plot against it)",
                             ParamPhase::build),
    };
    m.knob_rules = {KnobRule{
        {"command"}, [](const ParamSet& knobs) { return command_problem(knobs.text("command"), program_knobs(knobs)); }}};
    // What it models is its program's: it declares nothing, and the capability study measures it
    // (configs/experiments/study_capabilities.yaml with an entry for it).
    m.capabilities.notes = {{"reflection", "external declares no capability: what it models is its program's; add it "
                                           "to study_capabilities.yaml to measure that"}};
    m.runs_a_program = true;
    // The G-buffer's 12 channels and its encoded file, the image read back and its RGB copy.
    m.working_bytes_per_pixel = 12 * 4 * 2 + 4 * 4 + 3 * 4;
    m.counters = {counter_quantity("reported_ms", "ms",
                                   "the program's own time per frame, as its statistics file reports it (time_ms), mean "
                                   "over the frames; absent when it reports none",
                                   QuantityKind::timing)};
    return m;
  }();
  return info;
}

}  // namespace causticbench
