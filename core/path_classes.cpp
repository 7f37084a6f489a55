#include "core/path_classes.h"

namespace causticbench {

const char* path_interaction_name(PathInteraction interaction) {
  switch (interaction) {
    case PathInteraction::one_reflection: return "one_reflection";
    case PathInteraction::one_pass: return "one_pass";
    case PathInteraction::multiple: return "multiple";
  }
  return "multiple";
}

const char* path_interaction_capability(PathInteraction interaction) {
  switch (interaction) {
    case PathInteraction::one_reflection: return "reflection";
    case PathInteraction::one_pass: return "refraction";
    case PathInteraction::multiple: return "multiple_bounces";
  }
  return "multiple_bounces";
}

const char* path_light_name(PathLight light) {
  switch (light) {
    case PathLight::directional: return "directional";
    case PathLight::point: return "point";
    case PathLight::environment: return "environment";
  }
  return "environment";
}

const char* path_light_capability(PathLight light) {
  switch (light) {
    case PathLight::directional: return "directional_light";
    case PathLight::point: return "point_light";
    case PathLight::environment: return "environment_light";
  }
  return "environment_light";
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
