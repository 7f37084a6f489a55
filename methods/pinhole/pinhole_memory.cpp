// What pinhole's knobs cost in memory (CausticMethod::knob_memory), for the check before any work starts.
// Measured on the ring at 24x18 (issue 30, defect 4; tests/test_memory_cost.cpp), per knob:
//   samples S: the dense candidate set of D = max(20000, 4 S) surface points (28 bytes) and, for the
//     neighbourhood and grid samplings, the hash of cells it is thinned through; the reflector samples
//     (92 bytes, grown by push_back) and their per-frame and per-render arrays; 132 bytes a sample more
//     when update() runs again in the process (an experiment's repetitions);
//   environment_resolution R: the cube map's texels and its build's scratch layer (144 bytes a texel of
//     a face, R^2 a face), packed texels for a reflecting, unfiltered map lit everywhere (an environment
//     light), the own filter's padded mip levels (306 to 348), or OpenImageIO's lat-long map (336).
// The samples' bytes are upper bounds within 1.2 to 1.35x from 1e5 samples up; the map's within 1.05x.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "methods/pinhole/pinhole.h"

namespace causticbench {

std::vector<MemoryTerm> PinholeMethod::knob_memory(const PrepareContext& context, const ParamSet& knobs) const {
  const double samples = static_cast<double>(knobs.integer("samples"));
  const std::string sampling = knobs.text("sampling");
  const bool filtered = knobs.text("filtering") != "none";
  const double dense = sampling == "random" ? samples : std::max(20000.0, 4.0 * samples);
  const double per_point = sampling == "neighborhood" ? (filtered ? 165.0 : 120.0)
                           : sampling == "random"     ? (filtered ? 450.0 : 220.0)
                                                      : (filtered ? 130.0 : 85.0);
  const double sample_bytes = per_point * (sampling == "random" ? samples : dense) + 132.0 * samples;
  bool environment = false;
  for (const Light& light : context.scene.lights) environment = environment || light.kind == LightKind::environment_image || light.kind == LightKind::gaussian_spot;
  const double face = std::pow(static_cast<double>(knobs.integer("environment_resolution")), 2.0);
  bool refracts = false;  // some sampled object refracts: no packed copy of the map
  for (int object : pinhole_reflectors(context.scene, knobs.text("interaction")))
    refracts = refracts || pinhole_refracts(knobs.text("interaction"), context.scene.objects[object].material);
  const double per_texel = !filtered ? (environment && !refracts ? 168.0 : 144.0)
                           : knobs.text("filter_implementation") == "oiio" ? 336.0
                                                                           : (environment ? 348.0 : 306.0);
  return {MemoryTerm{{"samples"}, sample_bytes,
                     fmt::format("{:.3g} samples ({}): {:.3g} candidate points x {:.0f} bytes + 132 bytes a sample", samples,
                                 sampling, sampling == "random" ? samples : dense, per_point)},
          MemoryTerm{{"environment_resolution"}, 1.05 * per_texel * face,
                     fmt::format("{}^2 texels a face x {:.0f} bytes", knobs.integer("environment_resolution"),
                                 1.05 * per_texel)}};
}

}  // namespace causticbench
