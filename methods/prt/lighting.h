// A frame's lighting of one object as PRT takes it: the source radiance's spherical-harmonic coefficients
// per colour, in the object's build space, directions towards the light (Sloan, Kautz & Snyder 2002,
// Section 4: the lighting projected once a frame). Environment lights (an HDR map, the Gaussian spot)
// are projected in world space once per pose of the light and turned into build space by rotating their
// coefficients (harmonic_lighting.h); a directional light is its truncated delta; a point light is a
// directional light from the object's centre with the irradiance there (the assumption lpi and csl make
// too). A window then trades the truncation's ringing for blur.
#pragma once

#include <map>
#include <tuple>
#include <vector>

#include <glm/vec3.hpp>

#include "core/light.h"
#include "methods/common/build_space.h"
#include "methods/common/environment_quadrature.h"
#include "methods/common/harmonic_lighting.h"

namespace causticbench::prt {

struct FrameLighting {
  std::vector<double> coefficients[3];  // per colour, bands^2
  size_t quadrature_points = 0;         // environment points projected this frame (0: every projection cached)
};

class LightingProjector {
 public:
  explicit LightingProjector(int bands) : bands_(bands) {}
  // The lights of one frame as the object whose build space `map` maps into sees them (its centre at
  // `build_center`), windowed.
  FrameLighting project(const std::vector<LightFrame>& lights, const BuildSpaceMap& map, const Vec3& build_center,
                        HarmonicWindow window);
  // An environment light's world-space coefficients per colour (cached by light and pose).
  const std::vector<glm::dvec3>& world_coefficients(const LightFrame& light, size_t& projected_points);

 private:
  int bands_;
  std::map<std::tuple<const Light*, float, float, float>, std::vector<glm::dvec3>> cache_;
};

// The rotation part of a build-space map (its linear part divided by its scale), or nothing when the
// map scales unevenly (directions then do not turn rigidly: project the map's directions instead).
bool rigid_rotation(const glm::mat3& linear, glm::dmat3& rotation);

}  // namespace causticbench::prt
