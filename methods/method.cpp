#include "methods/method.h"

namespace causticbench {

std::vector<std::pair<std::string, bool>> Capabilities::entries() const {
  return {{"reflection", reflection},
          {"refraction", refraction},
          {"multiple_bounces", multiple_bounces},
          {"directional_light", directional_light},
          {"point_light", point_light},
          {"environment_light", environment_light},
          {"moving_light", moving_light},
          {"moving_objects", moving_objects},
          {"occlusion", occlusion},
          {"non_lambertian_receivers", non_lambertian_receivers}};
}

}  // namespace causticbench
