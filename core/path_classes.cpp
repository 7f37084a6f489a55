#include "core/path_classes.h"

#include <array>

namespace causticbench {

namespace {

// Indexed by the enums' values.
constexpr std::array<const char*, kPathInteractions> kInteractionNames = {"one_reflection", "one_pass", "multiple"};
constexpr std::array<const char*, kPathInteractions> kInteractionCapabilities = {"reflection", "refraction",
                                                                                 "multiple_bounces"};
constexpr std::array<const char*, kPathLights> kLightNames = {"directional", "point", "environment"};
constexpr std::array<const char*, kPathLights> kLightCapabilities = {"directional_light", "point_light",
                                                                     "environment_light"};
constexpr std::array<const char*, kPathReceivers> kReceiverNames = {"lambertian", "non_lambertian"};
constexpr std::array<const char*, kPathReceivers> kReceiverCapabilities = {"", "non_lambertian_receivers"};

}  // namespace

const char* path_interaction_name(PathInteraction interaction) {
  return kInteractionNames[static_cast<size_t>(interaction)];
}

const char* path_interaction_capability(PathInteraction interaction) {
  return kInteractionCapabilities[static_cast<size_t>(interaction)];
}

const char* path_light_name(PathLight light) { return kLightNames[static_cast<size_t>(light)]; }

const char* path_light_capability(PathLight light) { return kLightCapabilities[static_cast<size_t>(light)]; }

const char* path_receiver_name(PathReceiver receiver) { return kReceiverNames[static_cast<size_t>(receiver)]; }

const char* path_receiver_capability(PathReceiver receiver) {
  return kReceiverCapabilities[static_cast<size_t>(receiver)];
}

PathReceiver path_receiver_of(const Material& material) {
  // Only a purely diffuse surface is Lambertian; glossy and diffuse_mirror receivers have a specular part.
  return material.kind == MaterialKind::diffuse ? PathReceiver::lambertian : PathReceiver::non_lambertian;
}

PathLight path_light_of(LightKind kind) {
  switch (kind) {
    case LightKind::directional: return PathLight::directional;
    case LightKind::point: return PathLight::point;
    case LightKind::environment_image:
    case LightKind::gaussian_spot: return PathLight::environment;
  }
  return PathLight::environment;
}

void PathClassifier::reflection(int object, bool inside) {
  // Only a first event off an object's outside is one reflection; anything after a first event, and a
  // reflection inside glass, makes the path multiple.
  interaction_ = events_ == 0 && !inside ? PathInteraction::one_reflection : PathInteraction::multiple;
  ++events_;
}

void PathClassifier::refraction(int object, bool entering) {
  if (events_ == 0 && entering) {
    interaction_ = PathInteraction::one_pass;  // into the object: a pass begins
    object_ = object;
  } else if (!entering && interaction_ == PathInteraction::one_pass && !left_ && object == object_) {
    left_ = true;  // out of the same object with nothing between: the pass ends, still one
  } else {
    interaction_ = PathInteraction::multiple;
  }
  ++events_;
}

}  // namespace causticbench
