// Deterministic ray trees through specular objects: one ray split at every glass surface into its
// reflected and refracted children with the Fresnel weights, attenuated by mirrors' reflectance and
// by Beer-Lambert absorption inside glass, until each branch leaves the scene, meets a surface with a
// diffuse part, or falls below an energy threshold. Liu et al. 2008 (Section 3.1) trace their
// "caustic object rays" this way; the random-walk CausticPhotonTracer makes the same optical choices
// one at a time (core/photon_tracer.h). Both share core/optics.h.
#pragma once

#include <functional>

#include "core/tracer.h"

namespace causticbench {

// A branch that left the scene after at least one specular interaction.
struct ExitRay {
  Vec3 origin;     // the point of its last specular interaction (nudged off the surface)
  Vec3 direction;  // unit
  Color energy;    // what it carries, in the units of the energy the tree started with
  int depth = 0;   // specular interactions on its path
};

struct SpecularTreeSettings {
  // A branch whose largest channel falls below this fraction of the tree's starting energy is
  // dropped (its energy is counted as lost, never redistributed).
  float min_energy = 0.01f;
  int max_depth = 32;
};

// started = missed + exited + dropped + absorbed, to rounding (tests/test_specular_tree.cpp).
struct SpecularTreeStats {
  double started = 0.0;   // luminance of the energy that entered the trees
  double missed = 0.0;    // luminance of starting rays that met nothing (no specular interaction)
  double exited = 0.0;    // luminance that left the scene
  double dropped = 0.0;   // luminance below min_energy or beyond max_depth
  double absorbed = 0.0;  // luminance absorbed inside glass, by mirrors or met by a diffuse surface
  uint64_t rays = 0;      // rays intersected
  void add(const SpecularTreeStats& other) {
    started += other.started;
    missed += other.missed;
    exited += other.exited;
    dropped += other.dropped;
    absorbed += other.absorbed;
    rays += other.rays;
  }
};

// Traces the tree of `ray` carrying `energy` through the tracer's scene; calls `on_exit` for every
// branch that leaves it after a specular interaction (a ray that leaves without touching anything
// calls nothing). Branches are visited depth first, reflection before refraction, so the order is
// deterministic.
void trace_specular_tree(const Tracer& tracer, const Ray& ray, const Color& energy, const SpecularTreeSettings& settings,
                         SpecularTreeStats& stats, const std::function<void(const ExitRay&)>& on_exit);

}  // namespace causticbench
