// Caustic photon tracing, shared by the reference, the photon map and the precomputations of later
// methods. Photons leave the lights aimed only at the bounding spheres of specular objects, with the
// exact weights of that aiming (so no flux is lost or invented), bounce through any number of mirror
// and glass interactions (Fresnel, total internal reflection, Beer-Lambert absorption, Russian
// roulette), and are deposited where a path with at least one specular bounce meets a surface with a
// diffuse part.
#pragma once

#include <cstdint>
#include <vector>

#include "core/sampling.h"
#include "core/tracer.h"

namespace causticbench {

struct Photon {
  Vec3 position;
  Vec3 normal;     // geometric normal of the receiving surface, on the side the photon arrived from
  Vec3 direction;  // direction of travel
  Color power;     // flux of this one sample, in W: divide by the number of photons emitted
};

struct PhotonTracerSettings {
  uint64_t seed = 1;
  int max_bounces = 32;         // specular bounces before a path is cut
  int roulette_after = 4;       // bounces before Russian roulette starts
};

struct PhotonStats {
  uint64_t emitted = 0;
  uint64_t deposited = 0;
  uint64_t rays = 0;
  void add(const PhotonStats& other) {
    emitted += other.emitted;
    deposited += other.deposited;
    rays += other.rays;
  }
};

class CausticPhotonTracer {
 public:
  CausticPhotonTracer(const Tracer& tracer, PhotonTracerSettings settings);

  // Traces photons with indices [first, first + count). Photon i draws only from Random(seed, i), and
  // the output is in index order, so results do not depend on the thread count. Multithreaded.
  void trace(uint64_t first, uint64_t count, std::vector<Photon>& photons, PhotonStats& stats) const;
  // Traces one photon path; appends at most a few photons (one per receiving surface on the path).
  void trace_one(uint64_t index, std::vector<Photon>& photons, PhotonStats& stats) const;

  // Total flux (luminance, W) that the lights send towards the specular objects' bounding spheres.
  double aimed_flux() const { return total_weight_; }
  bool has_targets() const { return !targets_.empty(); }

 private:
  bool emit(Random& random, Ray& ray, Color& power) const;

  const Tracer& tracer_;
  PhotonTracerSettings settings_;
  std::vector<BoundingSphere> targets_;
  double target_area_ = 0.0;  // sum of the spheres' cross-sections
  Distribution1D light_choice_;
  double total_weight_ = 0.0;
};

}  // namespace causticbench
