// Static CSL generation for one object and one light direction (Liu et al. 2008, Section 3.1): the
// caustic object rays clustered into bundles (methods/csl/bundles.h), a spot light fitted to each
// (methods/csl/fit.h), the rays it cannot represent dismissed back into the pool, the rest splatted
// into its image (methods/csl/splat.h) and removed, until energy_coverage of the rays' energy is
// covered.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "methods/csl/bundles.h"
#include "methods/csl/fit.h"
#include "methods/csl/splat.h"

namespace causticbench::csl {

struct GenerateSettings {
  BundleSettings bundle;
  FitSettings fit;
  SplatSettings splat;
  double energy_coverage = 0.95;  // the paper's 95 %
  int max_lights = 64;            // spot lights per set at most
  double fit_tolerance = 0.05;    // |d - e| (about radians) beyond which a ray is dismissed
};

// What one spot light's creation measured, for the run record.
struct SpotLightRecord {
  int bundle_rays = 0;     // rays assigned to the bundle
  int kept_rays = 0;       // rays that fit and went into the image
  double energy = 0.0;     // their luminance energy (per unit irradiance)
  int bundle_iterations = 0;
  bool bundle_converged = false;
  Fit fit;
};

// The chord |d - e| between a ray's own direction and the spot light's ray from the same plane point (about
// the angle, in radians) beyond which the light it carries counts as misdirected: 0.1 rad moves the light
// a tenth of the way to its receiver. On the glass sphere, whose rays all meet the axis, 6 % of the ray
// energy is beyond it (most of it reflected upwards, where no receiver is); on a torus 62 % (README,
// "Misdirected light").
inline constexpr double kMisdirectedChord = 0.1;

struct SpotLightSet {
  Vec3 direction{0.0f, 1.0f, 0.0f};  // towards the light, build space
  std::vector<SpotLight> lights;
  std::vector<SpotLightRecord> records;
  double ray_energy = 0.0;      // luminance of every caustic object ray
  double covered_energy = 0.0;  // of it, in the lights' images
  // Of the covered energy, the rays a spot light sends more than kMisdirectedChord off their own direction:
  // light a point-focus spot light moves (a torus focuses on a ring, which no spot light's axis holds).
  double misdirected_energy = 0.0;
  int rays = 0;
  int seeds_tried = 0;          // seeds that gave a bundle or were retired
  double trace_seconds = 0.0, cluster_seconds = 0.0;

  size_t memory_bytes() const;
  nlohmann::json to_json() const;  // the record's summary (no images)
};

SpotLightSet generate_spot_lights(const ObjectRays& rays, const BoundingSphere& bounds, const GenerateSettings& settings);

}  // namespace causticbench::csl
