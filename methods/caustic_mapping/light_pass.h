// One light and one specular object of caustics mapping: the light views, the receiver map, the photon
// buffer, each photon's way out of the object and to its receiver, the caustic map it is splatted into.
// The method adds one such pass per light and specular object each frame (their caustic maps add).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/light.h"
#include "core/tracer.h"
#include "methods/common/light_view.h"
#include "methods/common/receivers.h"
#include "methods/param_dict.h"

namespace causticbench::caustic_mapping {

enum class SplatKind { point, gaussian, variable };

struct Settings {
  int photon_resolution = 512;
  int map_resolution = 512;
  int search_iterations = 5;
  // refraction: two_interface (Wyman 2005), one_interface, or auto: two where the photon buffer sees the
  // object's back along the light (a solid), one where it does not (a water surface, a sheet).
  enum class Refraction { automatic, two_interface, one_interface } refraction = Refraction::automatic;
  bool exact = false;         // intersection: exact (a ray) or image_space (the paper's search)
  bool refine = true;         // hit_position: plane (the ray meets the found receiver's plane) or texel (the paper's)
  SplatKind splat = SplatKind::variable;
  double splat_radius = 1.5;       // gaussian: radius in caustic-map texels
  double splat_photons = 16.0;     // variable: photons a splat should hold at the local density
  double max_splat_radius = 16.0;  // variable: the largest radius, texels
  static Settings from(const ParamSet& knobs);
};

// What a pass did with its photons, in photons and in flux (luminance of W, summed in a fixed order).
struct PassStatistics {
  uint64_t photons = 0;         // covered photon-buffer texels (one photon each)
  uint64_t landed = 0;          // splatted into the caustic map
  uint64_t search_failed = 0;   // the receiver search left the light view, found no receiver, or did not converge
  // Of those, the searches that could not start: the light sees no receiver behind the photon's own texel
  // (a light grazing the receivers sees past them; receivers outside its window). No search_iterations
  // recovers these: the lost flux's advice then names intersection: exact.
  uint64_t search_failed_at_start = 0;
  uint64_t second_interface_failed = 0;  // two_interface: total internal reflection, or the exit point off the object
  uint64_t outside_map = 0;     // found a receiver outside the caustic map's window, or one the light does not see
  uint64_t one_interface = 0;   // glass photons refracted at one interface (refraction: one_interface, or auto on a surface)
  double flux_leaving = 0.0;    // everything leaving the object that the method could model, plus what it cannot
  double flux_search_failed = 0.0, flux_search_failed_at_start = 0.0;
  double flux_second_interface = 0.0;
  double flux_outside_map = 0.0;
  double flux_not_modelled = 0.0;  // glass's Fresnel reflection: the method follows the refracted part only
  uint64_t search_steps = 0;       // receiver-map reads of the image-space search
  // A point light too close to its object for the photon buffer's widest window (80 degrees off its
  // axis): the light towards the object's bounding sphere beyond the window, an upper bound (the cone
  // holds directions that miss the object).
  double flux_outside_window = 0.0;
  void add(const PassStatistics& other);
};

// The receivers seen from the light: per texel of the caustic map's window, the first surface that is
// not a specular object (the scene rendered without them, as the paper does), and its depth from the
// light (LightView::project's); infinite where the texel sees nothing.
struct ReceiverMap {
  LightView view;
  int object = -1;  // the pass's object, not a receiver of its own light
  int resolution = 0;
  std::vector<Vec3> position;
  std::vector<Vec3> normal;
  std::vector<float> depth;
  // The texel holding window point (s, t), or -1 outside the window.
  long texel(double s, double t) const;
  // Side of a texel at `depth` from the light, in scene units.
  double texel_side(double depth) const;
  // Whether the light sees a point of this depth (projected at `at`) on a surface of unit `normal`: the
  // shadow-map test, the depth within a slope-scaled bias of the texel's (a texel's depth spans its side
  // times the tangent of the surface's slope to the light: twice that, plus a texel and a half for the
  // point's place in it). What the lookup asks of a receiver point, and a landing photon of its hit.
  bool sees(const LightView::Projected& at, long texel, const Vec3& point, const Vec3& normal) const;
};

// A photon leaving its object towards the receivers: what the light-view passes hand to the receiver
// search, on either backend (the Vulkan backend uploads them). lost_flux() follows the ones the search
// dropped with an exact ray afterwards, untimed, to tell light that meets a receiver (lost by the
// estimate) from light that leaves the scene (nothing to lose).
struct PhotonRay {
  Vec3 origin, direction;
  Color flux{0.0f};        // W
  Color absorption{0.0f};  // of the medium it travels in (one_interface), per scene unit
};

// What became of a photon's search: one definition for both backends (the Vulkan photon stage writes it;
// `none` is its photon-buffer texel that sent no photon).
enum class Landing : uint32_t { landed = 0, search_failed = 1, outside_map = 2, none = 3 };

// What a photon-buffer texel sent out of the object: where, which way, with what flux; or why nothing.
// The CPU computes it from the traced buffer, the Vulkan backend's leave stage from the rasterised one;
// both count it through count_leaving.
struct Outgoing {
  bool covered = false;        // a photon-buffer texel on the object
  bool second_failed = false;  // two_interface: no way out modelled
  bool one_interface = false;  // refracted once (into a medium the receivers lie in)
  Vec3 origin{0.0f}, direction{0.0f};
  Color flux{0.0f};            // after the interfaces and the absorption inside
  double not_modelled = 0.0;   // luminance of the flux the method does not follow (glass's Fresnel reflection)
  Color absorption{0.0f};      // one_interface: the medium's coefficient, applied over the way to the receiver
};

// What the CPU decides for a pass before either backend renders it, as the paper's author set up his
// shadow-map frusta: the photon buffer's light view (fitted to the object's bounding sphere), the caustic
// map's (fitted, with a margin, to where a probe of 32 x 32 photons meets the receivers with exact rays),
// how far behind its window an orthographic view starts, the light's strength (irradiance across a
// directional light, intensity of a point light).
struct PassPlan {
  bool valid = false;  // a light view exists (not for an environment)
  LightView photon_view, receiver_view;
  double back = 0.0;
  Color strength{0.0f};
  bool want_back = false;  // glass that may take two interfaces: the buffer holds back faces and d_N
  double flux_outside_window = 0.0;  // PassStatistics::flux_outside_window
};
PassPlan plan_pass(const Tracer& tracer, const LightFrame& light, int object, const Settings& settings);

struct LightPass {
  int object = -1;
  std::string light_name;
  PassPlan plan;
  ReceiverMap receivers;
  // Flux per caustic-map texel (RGB), then converted to flux per texel measure (LightView::texel_measure:
  // W/m^2 across the light for a directional light, W/sr from a point light), what the lookup reads.
  // Empty with backend: vulkan (the map stays on the device).
  std::vector<float> density;
  PassStatistics statistics;
  std::vector<PhotonRay> leaving;    // in photon-buffer texel order; second interfaces that failed are not here
  std::vector<uint32_t> dropped;     // indices into `leaving` of the photons the receiver search dropped
  std::vector<uint8_t> dropped_at_start;  // per dropped photon: its search failed at its start (count_landing)
  double photon_window_half_extent = 0.0;  // the photon buffer's window (scene units, or tan of the half-angle)
};

// The light-view half of a pass on the CPU: the plan, the photon buffer, each photon's way out of the
// object (pass.leaving, with the statistics of what left), the receiver map.
LightPass begin_pass(const Tracer& tracer, const LightFrame& light, int object, const Settings& settings);

// A pass with its plan only (the Vulkan backend renders the rest): the receiver map's view and resolution
// set, its texels empty.
LightPass planned_pass(const Tracer& tracer, const LightFrame& light, int object, const Settings& settings);

// Adds one photon-buffer texel's outcome to the statistics, and a photon that leaves to pass.leaving.
void count_leaving(LightPass& pass, const Outgoing& photon);

// Adds one searched photon to the statistics: `arriving` is what reaches its receiver (landed and
// outside_map), `steps` the receiver-map reads. Both backends count through it.
// `at_start`: a failed search whose first read, the receiver behind the photon's own texel, found none (or
// left the light's view); its callers decide (the CPU from the search's failure, the Vulkan backend from
// its step count), since a search of 0 iterations that starts but does not converge also reads once.
void count_landing(PassStatistics& statistics, const PhotonRay& photon, Landing landing, const Color& arriving, int steps,
                   bool at_start = false);

// The CPU backend's half: every photon of `pass.leaving` searched, counted, splatted into pass.density.
void land_and_splat(const Tracer& tracer, const Settings& settings, LightPass& pass);

// Everything one light and one specular object contribute to the frame on the CPU: both halves.
LightPass run_pass(const Tracer& tracer, const LightFrame& light, int object, const Settings& settings);

// E_c of `pass` at a receiver point, added into `irradiance`: the shadow-map test against the receiver map
// (a slope-scaled depth bias), then the caustic map's density, bilinear, converted to the surface.
void add_lookup(const LightPass& pass, const Vec3& point, const Vec3& normal, Color& irradiance);

}  // namespace causticbench::caustic_mapping
