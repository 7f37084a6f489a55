#include "methods/common/spherical_harmonics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace causticbench {

namespace {

void check_bands(int bands) {
  if (bands < 1 || bands > kMaxBands) {
    throw std::invalid_argument("spherical harmonics: " + std::to_string(bands) + " bands is not in 1 .. " +
                                std::to_string(kMaxBands));
  }
}

// Per k = l*l + l + m, m >= 0: scale = K_lm, times sqrt(2) for m > 0, times (2m-1)!! (the constant of
// P_m^m, folded in so the recurrence starts at 1); and the recurrence's factors (2l-1)/(l-m) and
// (l+m-1)/(l-m), so that evaluation divides nothing.
struct Factors {
  std::array<double, kMaxBands * kMaxBands> scale{}, along{}, back{};
};

const Factors& factors() {
  static const Factors table = [] {
    Factors f;
    for (int l = 0; l < kMaxBands; ++l) {
      for (int m = 0; m <= l; ++m) {
        double ratio = 1.0;  // (l-m)! / (l+m)!
        for (int k = l - m + 1; k <= l + m; ++k) ratio /= k;
        double double_factorial = 1.0;  // (2m-1)!!
        for (int k = 2 * m - 1; k > 1; k -= 2) double_factorial *= k;
        const int k = coefficient_index(l, m);
        f.scale[k] = std::sqrt((2 * l + 1) / (4.0 * kPiDouble) * ratio) * (m > 0 ? std::sqrt(2.0) : 1.0) * double_factorial;
        if (l > m) f.along[k] = (2.0 * l - 1.0) / (l - m), f.back[k] = (l + m - 1.0) / (l - m);
      }
    }
    return f;
  }();
  return table;
}

template <typename Real>
void evaluate_basis(int bands, Real x, Real y, Real z, Real* out) {
  check_bands(bands);
  const Factors& f = factors();
  Real cosine = 1, sine = 0;  // (x + i y)^m
  for (int m = 0; m < bands; ++m) {
    Real before = 0, current = 1;  // Q_{l-1}^m, Q_l^m at l = m
    for (int l = m; l < bands; ++l) {
      if (l > m) {  // at l = m + 1, before is 0: Q_{m+1}^m = (2m+1) z Q_m^m
        const int k = coefficient_index(l, m);
        const Real next = static_cast<Real>(f.along[k]) * z * current - static_cast<Real>(f.back[k]) * before;
        before = current, current = next;
      }
      const Real radial = static_cast<Real>(f.scale[coefficient_index(l, m)]) * current;
      if (m == 0) {
        out[coefficient_index(l, 0)] = radial;
      } else {
        out[coefficient_index(l, m)] = radial * cosine;
        out[coefficient_index(l, -m)] = radial * sine;
      }
    }
    const Real next_cosine = x * cosine - y * sine;
    sine = x * sine + y * cosine, cosine = next_cosine;
  }
}

}  // namespace

std::vector<float> basis_factors(int bands) {
  check_bands(bands);
  const Factors& f = factors();
  const size_t n2 = static_cast<size_t>(bands) * bands;
  std::vector<float> out(3 * n2);
  for (size_t k = 0; k < n2; ++k) {
    out[k] = static_cast<float>(f.scale[k]);
    out[n2 + k] = static_cast<float>(f.along[k]);
    out[2 * n2 + k] = static_cast<float>(f.back[k]);
  }
  return out;
}

namespace {

template <typename Direction>
std::vector<double> project_samples(int bands, const std::vector<Direction>& directions,
                                    const std::vector<double>& weights, const std::vector<double>& values) {
  const int count = coefficient_count(bands);
  if (weights.size() != directions.size() || values.size() != directions.size()) {
    throw std::invalid_argument("spherical harmonics: project needs as many weights and values as directions");
  }
  std::vector<double> coefficients(count, 0.0);
  std::array<double, kMaxBands * kMaxBands> basis;
  for (size_t i = 0; i < directions.size(); ++i) {
    evaluate(bands, glm::dvec3(directions[i]), basis.data());
    const double weighted = weights[i] * values[i];
    for (int k = 0; k < count; ++k) coefficients[k] += weighted * basis[k];
  }
  return coefficients;
}

void check_coefficients(int bands, const std::vector<double>& coefficients) {
  if (static_cast<int>(coefficients.size()) != coefficient_count(bands)) {
    throw std::invalid_argument("spherical harmonics: " + std::to_string(coefficients.size()) + " coefficients for " +
                                std::to_string(bands) + " bands");
  }
}

}  // namespace

int coefficient_count(int bands) {
  check_bands(bands);
  return bands * bands;
}

void evaluate(int bands, const Vec3& d, float* out) { evaluate_basis<float>(bands, d.x, d.y, d.z, out); }
void evaluate(int bands, const glm::dvec3& d, double* out) { evaluate_basis<double>(bands, d.x, d.y, d.z, out); }

void gauss_legendre(int nodes, std::vector<double>& abscissas, std::vector<double>& weights) {
  abscissas.clear(), weights.clear();
  for (int i = 0; i < nodes; ++i) {
    double z = std::cos(kPiDouble * (i + 0.75) / (nodes + 0.5)), derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double before = 1.0, current = z;  // P_0, P_1, up to P_nodes
      for (int k = 2; k <= nodes; ++k) {
        const double next = ((2 * k - 1) * z * current - (k - 1) * before) / k;
        before = current, current = next;
      }
      derivative = nodes * (z * current - before) / (z * z - 1.0);
      const double step = current / derivative;
      z -= step;
      if (std::fabs(step) < 1e-16) break;
    }
    abscissas.push_back(z);
    weights.push_back(2.0 / ((1.0 - z * z) * derivative * derivative));
  }
}

SphereQuadrature product_quadrature(int bands) {
  check_bands(bands);
  // Gauss-Legendre with g nodes is exact to degree 2g - 1 in z; the uniform azimuths sum e^(i k phi)
  // exactly for |k| below their count; a polynomial of degree 2 bands needs both up to 2 bands.
  const int nodes = bands + 1, azimuths = 2 * bands + 1;
  std::vector<double> zs, z_weights;
  gauss_legendre(nodes, zs, z_weights);
  SphereQuadrature quadrature;
  for (int i = 0; i < nodes; ++i) {
    const double z = zs[static_cast<size_t>(i)];
    const double weight = z_weights[static_cast<size_t>(i)] * (2.0 * kPiDouble / azimuths);
    const double sine = std::sqrt(std::max(0.0, 1.0 - z * z));
    for (int j = 0; j < azimuths; ++j) {
      const double phi = 2.0 * kPiDouble * j / azimuths;
      quadrature.directions.push_back({sine * std::cos(phi), sine * std::sin(phi), z});
      quadrature.weights.push_back(weight);
    }
  }
  return quadrature;
}

std::vector<double> project(int bands, const std::vector<glm::dvec3>& directions, const std::vector<double>& weights,
                            const std::vector<double>& values) {
  return project_samples(bands, directions, weights, values);
}

std::vector<double> project(int bands, const std::vector<Vec3>& directions, const std::vector<double>& weights,
                            const std::vector<double>& values) {
  return project_samples(bands, directions, weights, values);
}

double reconstruct(int bands, const std::vector<double>& coefficients, const glm::dvec3& d) {
  check_coefficients(bands, coefficients);
  std::array<double, kMaxBands * kMaxBands> basis;
  evaluate(bands, d, basis.data());
  double sum = 0.0;
  for (size_t k = 0; k < coefficients.size(); ++k) sum += coefficients[k] * basis[k];
  return sum;
}

double reconstruct(int bands, const std::vector<double>& coefficients, const Vec3& d) {
  return reconstruct(bands, coefficients, glm::dvec3(d));
}

std::vector<double> band_energies(int bands, const std::vector<double>& coefficients) {
  check_coefficients(bands, coefficients);
  std::vector<double> energies(bands, 0.0);
  for (int l = 0; l < bands; ++l) {
    for (int m = -l; m <= l; ++m) energies[l] += coefficients[coefficient_index(l, m)] * coefficients[coefficient_index(l, m)];
  }
  return energies;
}

}  // namespace causticbench
