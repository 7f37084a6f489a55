// Caustic photon tracing, shared by the reference, the photon map and the precomputations of later
// methods. Photons leave the lights aimed only at the bounding spheres of target objects (by default
// the frame's lights and its specular objects), with the exact weights of that aiming (so no flux is
// lost or invented), bounce through any number of mirror and glass interactions with every object of
// the scene (Fresnel, total internal reflection, Beer-Lambert absorption, Russian roulette), and are
// deposited where a path with at least one specular bounce meets a surface with a diffuse part.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include "core/path_classes.h"
#include "core/ray_differential.h"
#include "core/sampling.h"
#include "core/tracer.h"

namespace causticbench {

struct Photon {
  Vec3 position;
  Vec3 normal;     // geometric normal of the receiving surface, on the side the photon arrived from
  Vec3 direction;  // direction of travel
  Color power;     // flux of this one sample, in W: divide by the number of photons emitted
};

// A straight piece of a photon path after the path's first specular bounce, in air or inside glass:
// what volume estimators such as Wyman 2003's local irradiance volumes accumulate.
struct PathSegment {
  Vec3 origin;
  Vec3 direction;  // unit
  float length;    // to the next surface; infinite when the photon leaves the scene
  Color power;     // flux carried along it (inside glass: at its middle), in W: divide by the number emitted
};

struct PhotonTracerSettings {
  uint64_t seed = 1;
  int max_bounces = 32;         // specular bounces before a path is cut
  int roulette_after = 4;       // bounces before Russian roulette starts
  // 0: every emission draws from Random(seed, index). N > 0: stratified emission in passes of N photons:
  // photon index i is point i mod N of pass i / N's randomised Sobol sequence (core/low_discrepancy.h)
  // for where it leaves the light and where it aims (the disk across a target for a distant light, the
  // cone towards it for a point light, then the light's own sampling, the target and the light chosen);
  // its path after emission still draws from Random(seed, i). Each pass is an unbiased, independent
  // replicate whose photons cover the emission evenly.
  uint64_t stratified_pass_size = 0;
};

struct PhotonStats {
  uint64_t emitted = 0;
  uint64_t deposited = 0;
  uint64_t rays = 0;
  uint64_t cut = 0;        // paths still bouncing after max_bounces (their flux never lands)
  double cut_flux = 0.0;   // their luminance flux, W (as the photons carry it)
  void add(const PhotonStats& other) {
    emitted += other.emitted;
    deposited += other.deposited;
    rays += other.rays;
    cut += other.cut;
    cut_flux += other.cut_flux;
  }
};

// Lights that are not the scene's, for precomputations that shoot photons for any light direction
// (Wyman 2003's light samples, Liu 2008's icosahedron directions). A LightFrame points at its Light,
// so the lights live in a deque, whose elements never move: the frames stay valid as lights are
// added and when the whole set is moved. Copying would leave the copy's frames pointing at the
// original's lights, so it is not allowed. Keep the set alive while a tracer made from it is in use.
class PhotonLights {
 public:
  PhotonLights() = default;
  PhotonLights(const PhotonLights&) = delete;
  PhotonLights& operator=(const PhotonLights&) = delete;
  PhotonLights(PhotonLights&&) = default;
  PhotonLights& operator=(PhotonLights&&) = default;

  // A distant light arriving from `direction_to_light` (any non-zero length), with `irradiance` in
  // W/m^2 on a surface facing it, from a disk of `solid_angle_sr` (0: a perfectly parallel beam).
  void add_directional(Vec3 direction_to_light, Color irradiance, double solid_angle_sr = 0.0);
  // A point light of `intensity_w_per_sr`, emitting from a sphere of `radius` (0: a true point).
  void add_point(Vec3 position, Color intensity_w_per_sr, double radius = 0.0);
  // A posed scene light, as it is: it keeps pointing at the scene's Light, which must outlive it.
  void add(const LightFrame& light);

  const std::vector<LightFrame>& frames() const { return frames_; }

 private:
  std::deque<Light> lights_;
  std::vector<LightFrame> frames_;
};

class CausticPhotonTracer {
 public:
  // Emits from the frame's lights towards its specular objects.
  CausticPhotonTracer(const Tracer& tracer, PhotonTracerSettings settings);
  // Emits only from `lights` (copied; the Lights they point at must outlive the tracer) and aims only
  // at the bounding spheres of `target_objects` (indices into the scene's objects, each at most
  // once; std::invalid_argument otherwise). Photons still interact with every object of the scene.
  CausticPhotonTracer(const Tracer& tracer, PhotonTracerSettings settings, const std::vector<LightFrame>& lights,
                      const std::vector<int>& target_objects);

  // Traces photons with indices [first, first + count). Photon i draws only from Random(seed, i), and
  // the output is in index order, so results do not depend on the thread count. Multithreaded.
  void trace(uint64_t first, uint64_t count, std::vector<Photon>& photons, PhotonStats& stats) const;
  // The same, and each photon's path class (core/path_classes.h, PathClass::packed) appended to `classes`,
  // one per photon, in the same order. (An overload, not a defaulted parameter: plugins built against the
  // SDK link the four-argument trace; `blocked`, new in SDK version 3, is defaulted.)
  // With `blocked`, also the paths an occluder blocks (core/path_classes.h, occlusion), each followed on
  // through the blocking surface as if it were not there and recorded where it would have arrived, with its
  // class (PathClass::blocked set). Two kinds: a path blocked on its way from the light to its first
  // specular object (followed while it still heads for a target's world box; recorded at its first
  // receiver met from the front of a solid or either side of an open surface, then ended), and a photon that
  // reached a receiver, continued straight through it (recorded at every further receiver it meets so, up to
  // max_bounces surfaces; ended at a specular object). The second kind is traced only where the
  // box of a receiver lies ahead (the one reached left out if it is a quad or a disk), so that a floor under
  // glass costs no ray. Blocked paths draw only their own photon's random numbers:
  // the photons that arrive are the same with or without `blocked`.
  struct Blocked {
    std::vector<Photon> photons;
    std::vector<uint8_t> classes;
  };
  void trace(uint64_t first, uint64_t count, std::vector<Photon>& photons, PhotonStats& stats,
             std::vector<uint8_t>& classes, Blocked* blocked = nullptr) const;
  // Traces one photon path; appends at most a few photons (one per receiving surface on the path).
  void trace_one(uint64_t index, std::vector<Photon>& photons, PhotonStats& stats) const;
  // Traces the same path as trace_one(index) and calls `visit` for each of its PathSegments, in order.
  void trace_segments(uint64_t index, PhotonStats& stats, const std::function<void(const PathSegment&)>& visit) const;

  // A photon the caller emits (its own emission map: methods/rt_photons), from `ray` with `power` (W, as
  // emit() gives them) and the ray differentials of its emission, carried through every specular
  // interaction (core/ray_differential.h). Its path draws from Random(seed, index) as trace_one's does
  // after emission. `visit(hit, arrival_normal, direction, power, differential)` where it meets a
  // receiver after at least one specular bounce, the differential transferred to that hit.
  using DifferentialVisit =
      std::function<void(const SurfaceHit&, const Vec3&, const Vec3&, const Color&, const RayDifferential&)>;
  void trace_emitted(uint64_t index, const Ray& ray, const Color& power, RayDifferential differential,
                     PhotonStats& stats, const DifferentialVisit& visit) const;

  // Total flux (luminance, W) that the lights send towards the targets' bounding spheres.
  double aimed_flux() const { return total_weight_; }
  // Sum of the targets' bounding-sphere cross-sections, pi r^2 each (m^2): the area a directional
  // light's photons are aimed through, so that its aimed flux is luminance(E) times this.
  double target_cross_section() const { return target_area_; }
  bool has_targets() const { return !targets_.empty(); }

 private:
  class EmissionDraws;
  void trace_blocks(uint64_t first, uint64_t count, std::vector<Photon>& photons, PhotonStats& stats,
                    std::vector<uint8_t>* classes, Blocked* blocked) const;
  void trace_path(uint64_t index, std::vector<Photon>& photons, PhotonStats& stats, std::vector<uint8_t>* classes,
                  Blocked* blocked) const;
  // Where a blocked path is recorded: hit, arrival normal, direction, power, class.
  using BlockedVisit = std::function<void(const SurfaceHit&, const Vec3&, const Vec3&, const Color&, uint8_t)>;
  // The straight continuation of a photon that reached a receiver at `hit`, through it (the second kind of
  // blocked path above).
  void follow_through_receivers(const SurfaceHit& hit, const Vec3& direction, const Color& power, PathClass path,
                                PhotonStats& stats, const BlockedVisit& on_blocked) const;
  // Whether a ray from `origin` along `direction` still meets a target's world box ahead.
  bool heads_for_a_target(const Vec3& origin, const Vec3& direction) const;
  static bool meets_sphere_ahead(const BoundingSphere& sphere, const Vec3& origin, const Vec3& direction);
  struct WorldBox;
  static bool meets_box_ahead(const WorldBox& box, const Vec3& origin, const Vec3& direction);
  // A solid (sphere, box, prism, torus, a ring with a wall): its inside faces are passed through.
  static bool is_closed(const ShapeDesc& shape);
  // Whether a blocked path is recorded at `hit` met along `direction`: from the front of a solid, or either
  // side of an open surface (quad, disk, a thin ring, cup, paraboloid, water, mesh).
  bool records_blocked_on(const SurfaceHit& hit, const Vec3& direction) const;
  // Draws an emission: its ray, its power and the kind of light it left.
  bool emit(EmissionDraws& draws, Ray& ray, Color& power, PathLight& light) const;
  template <class OnReceiver, class OnSegment>
  void walk(uint64_t index, PhotonStats& stats, OnReceiver&& on_receiver, OnSegment&& on_segment,
            const BlockedVisit* on_blocked = nullptr) const;
  template <class OnReceiver, class OnSegment>
  void follow(Random& random, Ray ray, Color power, PathLight light, RayDifferential* differential, PhotonStats& stats,
              OnReceiver&& on_receiver, OnSegment&& on_segment, const BlockedVisit* on_blocked = nullptr) const;

  const Tracer& tracer_;
  PhotonTracerSettings settings_;
  std::vector<LightFrame> lights_;
  std::vector<BoundingSphere> targets_;
  double target_area_ = 0.0;  // sum of the spheres' cross-sections
  // An object's world box (Blocked): the receivers' (what may stand behind a receiver) and the targets'
  // (what a blocked path still heads for).
  struct WorldBox {
    int object = 0;
    Vec3 lower, upper;
  };
  std::vector<WorldBox> receivers_, target_boxes_;
  Distribution1D light_choice_;
  double total_weight_ = 0.0;
};

}  // namespace causticbench
