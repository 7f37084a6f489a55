#include "methods/prt/band_limit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "methods/common/spherical_harmonics.h"
#include "methods/prt/transfer.h"

namespace causticbench::prt {

int response_bands(int source_directions) {
  return std::clamp(static_cast<int>(std::sqrt(source_directions / 2.0)), 1, kMaxBands);
}

ResponseHarmonics response_harmonics(const std::vector<double>& responses) {
  if (responses.size() % 3 != 0 || responses.empty())
    throw std::invalid_argument("prt::response_harmonics: not 3 values a source direction");
  const std::vector<Vec3> directions = fibonacci_directions(static_cast<int>(responses.size() / 3));
  const std::vector<double> weights(directions.size(), 4.0 * kPiDouble / static_cast<double>(directions.size()));
  ResponseHarmonics harmonics;
  harmonics.bands = response_bands(static_cast<int>(directions.size()));
  double total = 0.0, top = 0.0;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> values(directions.size());
    for (size_t s = 0; s < directions.size(); ++s) values[s] = responses[3 * s + static_cast<size_t>(c)];
    harmonics.coefficients[c] = project(harmonics.bands, directions, weights, values);
    const std::vector<double> energies = band_energies(harmonics.bands, harmonics.coefficients[c]);
    for (double energy : energies) total += energy;
    top += energies.back();
  }
  harmonics.top_band_share = total > 0.0 ? top / total : 0.0;
  return harmonics;
}

BandLimitEnergy band_limit_energy(const ResponseHarmonics& response, int bands, const std::vector<float>& used,
                                  const std::vector<double> full[3]) {
  const size_t n2 = static_cast<size_t>(bands) * bands, all = static_cast<size_t>(response.bands) * response.bands;
  if (used.size() != 3 * n2 || n2 > all) throw std::invalid_argument("prt::band_limit_energy: lighting sizes");
  BandLimitEnergy energy;
  for (int c = 0; c < 3; ++c) {
    if (full[c].size() != all || response.coefficients[c].size() != all)
      throw std::invalid_argument("prt::band_limit_energy: the full lighting is not response.bands^2 coefficients");
    for (size_t j = 0; j < all; ++j) energy.full += response.coefficients[c][j] * full[c][j];
    for (size_t j = 0; j < n2; ++j) energy.band_limited += response.coefficients[c][j] * used[c * n2 + j];
  }
  return energy;
}

}  // namespace causticbench::prt
