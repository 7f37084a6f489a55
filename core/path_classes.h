// The light-path classes of caustic light, in the capability names' terms (methods/method.h,
// Capabilities; issue 52): what a scene requires of a method is the share of its caustic flux in each
// class, which the reference measures while it converges (methods/reference/README.md, "What a scene
// requires"). A caustic path is classed by its specular interactions and by the kind of light it left:
//
//   one_reflection  exactly one specular event, a reflection off the outside of an object (a mirror, or
//                   the Fresnel reflection off glass): `reflection`;
//   one_pass        one pass through one refracting object and nothing else: in through its surface and
//                   out again with no reflection between, or in through an open surface (water) to a
//                   receiver inside its medium: `refraction`;
//   multiple        everything else that reaches a receiver: two or more reflections, a reflection inside
//                   glass, a reflection and a refraction, two objects, or the same object entered twice (a
//                   torus's arm-to-arm path leaves one arm and enters the other: two passes): `multiple_bounces`.
//
// The light classes are the light kinds a method declares it models: directional, point, environment
// (an image or a procedural Gaussian spot over the sphere of directions). The receiver classes: a
// Lambertian (diffuse) receiver, or one with a specular part (glossy, diffuse_mirror):
// `non_lambertian_receivers`.
//
// Occlusion is not a class of the light that arrives but light that does not: a path whose way from the
// light to its first specular object, or from its last one on to a receiver behind the one it reached,
// is blocked by a surface that is not specular. A method that does not model occlusion lets that light
// through. The reference follows such a path on as a "blocked" path (PathClass::blocked), through the
// blocking surface, to the receiver it would have reached: core/photon_tracer.h, trace with `blocked`.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "core/light.h"
#include "core/material.h"

namespace causticbench {

enum class PathInteraction : uint8_t { one_reflection = 0, one_pass = 1, multiple = 2 };
enum class PathLight : uint8_t { directional = 0, point = 1, environment = 2 };
enum class PathReceiver : uint8_t { lambertian = 0, non_lambertian = 1 };

inline constexpr int kPathInteractions = 3;
inline constexpr int kPathLights = 3;
inline constexpr int kPathReceivers = 2;
// The capability a method needs to keep blocked light out (Capabilities::occlusion).
inline constexpr const char* kOcclusionCapability = "occlusion";

// The name used in records and reports, and the capability each class needs.
const char* path_interaction_name(PathInteraction interaction);
const char* path_interaction_capability(PathInteraction interaction);
const char* path_light_name(PathLight light);
const char* path_light_capability(PathLight light);
PathLight path_light_of(LightKind kind);
// "lambertian", "non_lambertian"; the capability "" (every method takes a Lambertian receiver) or
// "non_lambertian_receivers".
const char* path_receiver_name(PathReceiver receiver);
const char* path_receiver_capability(PathReceiver receiver);
PathReceiver path_receiver_of(const Material& material);

// A photon's class packed in one byte: the interaction in the low two bits, the light in the next two,
// the receiver in bit 4, and bit 5 set on a blocked path (light an occluder took).
struct PathClass {
  PathInteraction interaction = PathInteraction::one_reflection;
  PathLight light = PathLight::directional;
  PathReceiver receiver = PathReceiver::lambertian;
  bool blocked = false;
  uint8_t packed() const {
    return static_cast<uint8_t>(static_cast<uint8_t>(interaction) | (static_cast<uint8_t>(light) << 2) |
                                (static_cast<uint8_t>(receiver) << 4) | (blocked ? 32u : 0u));
  }
  static PathClass unpack(uint8_t byte) {
    return {static_cast<PathInteraction>(byte & 3u), static_cast<PathLight>((byte >> 2) & 3u),
            static_cast<PathReceiver>((byte >> 4) & 1u), (byte & 32u) != 0};
  }
};

// Follows one path's specular events in order and says its interaction class at any point. `object` is
// the scene object of the event; `inside` whether the photon travelled inside a refracting medium before
// it (an internal reflection, or the refraction that leaves the medium).
class PathClassifier {
 public:
  void reflection(int object, bool inside);
  void refraction(int object, bool entering);
  PathInteraction interaction() const { return interaction_; }
  int events() const { return events_; }

 private:
  PathInteraction interaction_ = PathInteraction::one_reflection;
  int events_ = 0;
  int object_ = -1;
  bool left_ = false;  // the one pass has left its object
};

}  // namespace causticbench
