#include "metrics/caustic_presence.h"

#include <fmt/format.h>

#include "core/image_statistics.h"

namespace causticbench {

const char* const kEmptyCausticHint =
    "check that the camera sees the surfaces the caustic should fall on, that the lights reach the specular "
    "(mirror or glass) objects, and that those objects send light towards the surfaces in view";

bool CausticPresence::empty() const {
  return receiver_pixels == 0 || !(caustic_sum > kEmptyCausticFraction * direct_sum);
}

std::string CausticPresence::describe() const {
  if (receiver_pixels == 0) return "the camera sees no receiver pixel (no surface with a diffuse part is in view)";
  return fmt::format("E_c summed over its {} receiver pixels is {:.6g} W/m^2, {} {:g} of the direct irradiance summed "
                     "over them ({:.6g} W/m^2)",
                     receiver_pixels, caustic_sum, empty() ? "not above" : "above", kEmptyCausticFraction, direct_sum);
}

CausticPresence measure_caustic_presence(const Image& caustic, const Image& direct,
                                         const std::vector<uint8_t>& receivers) {
  CausticPresence presence;
  for (uint8_t receiver : receivers) presence.receiver_pixels += receiver ? 1 : 0;
  presence.caustic_sum = masked_sum(caustic, receivers);
  presence.direct_sum = masked_sum(direct, receivers);
  return presence;
}

}  // namespace causticbench
