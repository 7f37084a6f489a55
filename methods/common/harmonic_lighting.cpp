#include "methods/common/harmonic_lighting.h"

#include <cmath>
#include <stdexcept>

namespace causticbench {

HarmonicRotation::HarmonicRotation(int bands, const glm::dmat3& rotation) : bands_(bands) {
  const int count = coefficient_count(bands);
  blocks_.resize(static_cast<size_t>(bands));
  for (int l = 0; l < bands; ++l) blocks_[static_cast<size_t>(l)].assign(static_cast<size_t>((2 * l + 1) * (2 * l + 1)), 0.0);
  const SphereQuadrature quadrature = product_quadrature(bands);
  std::vector<double> turned(static_cast<size_t>(count)), plain(static_cast<size_t>(count));
  for (size_t q = 0; q < quadrature.directions.size(); ++q) {
    evaluate(bands, rotation * quadrature.directions[q], turned.data());
    evaluate(bands, quadrature.directions[q], plain.data());
    const double weight = quadrature.weights[q];
    for (int l = 0; l < bands; ++l) {
      std::vector<double>& block = blocks_[static_cast<size_t>(l)];
      const int side = 2 * l + 1, first = l * l;
      for (int row = 0; row < side; ++row) {
        const double a = weight * turned[static_cast<size_t>(first + row)];
        for (int column = 0; column < side; ++column) block[static_cast<size_t>(row * side + column)] += a * plain[static_cast<size_t>(first + column)];
      }
    }
  }
}

std::vector<double> HarmonicRotation::apply(const std::vector<double>& coefficients) const {
  if (coefficients.size() != static_cast<size_t>(coefficient_count(bands_)))
    throw std::invalid_argument("HarmonicRotation::apply: expected bands^2 coefficients");
  std::vector<double> result(coefficients.size(), 0.0);
  for (int l = 0; l < bands_; ++l) {
    const std::vector<double>& block = blocks_[static_cast<size_t>(l)];
    const int side = 2 * l + 1, first = l * l;
    for (int row = 0; row < side; ++row) {
      double sum = 0.0;
      for (int column = 0; column < side; ++column) sum += block[static_cast<size_t>(row * side + column)] * coefficients[static_cast<size_t>(first + column)];
      result[static_cast<size_t>(first + row)] = sum;
    }
  }
  return result;
}

double clamped_cosine(int l) {
  if (l < 0) throw std::invalid_argument("clamped_cosine: l must not be negative");
  if (l == 0) return kPiDouble;
  if (l == 1) return 2.0 * kPiDouble / 3.0;
  if (l % 2 == 1) return 0.0;
  // Ramamoorthi & Hanrahan 2001, Eq. 9: 2 pi (-1)^(l/2 - 1) / ((l + 2)(l - 1)) * l! / (2^l ((l/2)!)^2).
  double ratio = 1.0;  // l! / (2^l ((l/2)!)^2) = C(l, l/2) / 2^l, built up as a product to stay exact
  for (int k = 1; k <= l / 2; ++k) ratio *= static_cast<double>(l / 2 + k) / (4.0 * k);
  const double sign = (l / 2 - 1) % 2 == 0 ? 1.0 : -1.0;
  return 2.0 * kPiDouble * sign / ((l + 2.0) * (l - 1.0)) * ratio;
}

double irradiance_at(int bands, const std::vector<double>& coefficients, const glm::dvec3& normal) {
  const int count = coefficient_count(bands);
  if (coefficients.size() != static_cast<size_t>(count))
    throw std::invalid_argument("irradiance_at: expected bands^2 coefficients");
  double basis[kMaxBands * kMaxBands];
  evaluate(bands, normal, basis);
  double sum = 0.0;
  for (int l = 0; l < bands; ++l) {
    double band = 0.0;
    for (int m = -l; m <= l; ++m) band += coefficients[static_cast<size_t>(coefficient_index(l, m))] * basis[coefficient_index(l, m)];
    sum += clamped_cosine(l) * band;
  }
  return sum;
}

HarmonicWindow harmonic_window(const std::string& name) {
  if (name == "none") return HarmonicWindow::none;
  if (name == "hanning") return HarmonicWindow::hanning;
  if (name == "lanczos") return HarmonicWindow::lanczos;
  throw std::invalid_argument("harmonic_window: expected none, hanning or lanczos, found '" + name + "'");
}

double window_factor(HarmonicWindow window, int l, int bands) {
  const double x = kPiDouble * l / bands;
  switch (window) {
    case HarmonicWindow::none: return 1.0;
    case HarmonicWindow::hanning: return 0.5 * (1.0 + std::cos(x));
    case HarmonicWindow::lanczos: return l == 0 ? 1.0 : std::sin(x) / x;
  }
  return 1.0;
}

void apply_window(HarmonicWindow window, int bands, std::vector<double>& coefficients) {
  if (coefficients.size() != static_cast<size_t>(coefficient_count(bands)))
    throw std::invalid_argument("apply_window: expected bands^2 coefficients");
  for (int l = 0; l < bands; ++l)
    for (int m = -l; m <= l; ++m) coefficients[static_cast<size_t>(coefficient_index(l, m))] *= window_factor(window, l, bands);
}

std::vector<double> directional_coefficients(int bands, const glm::dvec3& towards_light, double irradiance) {
  std::vector<double> coefficients(static_cast<size_t>(coefficient_count(bands)));
  evaluate(bands, glm::normalize(towards_light), coefficients.data());
  for (double& value : coefficients) value *= irradiance;
  return coefficients;
}

}  // namespace causticbench
