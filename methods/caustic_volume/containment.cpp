// Whether a receiver point lies inside a caustic volume, on which sheets, and what it receives there.
#include <algorithm>
#include <cmath>

#include "methods/caustic_volume/volume.h"

namespace causticbench::caustic_volume {

void finish_volume(Volume& volume) {
  const glm::dvec3 a1 = volume.origin[1] - volume.origin[0], a2 = volume.origin[2] - volume.origin[0];
  const glm::dvec3 b1 = volume.direction[1] - volume.direction[0], b2 = volume.direction[2] - volume.direction[0];
  volume.k = {glm::cross(a1, a2), glm::cross(a1, b2) + glm::cross(b1, a2), glm::cross(b1, b2)};
  for (int j = 0; j < 3; ++j) volume.k_dot_d0[j] = glm::dot(volume.k[j], volume.direction[0]);
  volume.lower = glm::dvec3(std::numeric_limits<double>::infinity());
  volume.upper = -volume.lower;
  for (int i = 0; i < 3; ++i)
    for (double t : {0.0, volume.t_max}) {
      const glm::dvec3 corner = volume.origin[i] + t * volume.direction[i];
      volume.lower = glm::min(volume.lower, corner);
      volume.upper = glm::max(volume.upper, corner);
    }
}

namespace {

// A root of g in [lo, hi] where g(lo) and g(hi) differ in sign: the Illinois variant of regula falsi,
// which converges superlinearly and never leaves the bracket (a step that would is a bisection). Done when
// |g| is within rounding of the polynomial's size `scale`, or the bracket is.
template <class G>
double bracketed_root(G g, double lo, double hi, double g_lo, double g_hi, double scale) {
  int side = 0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    double mid = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
    if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);
    const double g_mid = g(mid);
    if (std::abs(g_mid) <= 1e-15 * scale || hi - lo <= 1e-15) return mid;
    if ((g_mid < 0.0) == (g_lo < 0.0)) {
      lo = mid, g_lo = g_mid;
      if (side == -1) g_hi *= 0.5;
      side = -1;
    } else {
      hi = mid, g_hi = g_mid;
      if (side == 1) g_lo *= 0.5;
      side = 1;
    }
  }
  return std::abs(g_lo) < std::abs(g_hi) ? lo : hi;
}

}  // namespace

int cubic_roots(double c0, double c1, double c2, double c3, double t_max, double roots[3]) {
  // In u = t / t_max on [0, 1], so that the coefficients compare.
  const double a0 = c0, a1 = c1 * t_max, a2 = c2 * t_max * t_max, a3 = c3 * t_max * t_max * t_max;
  auto g = [&](double u) { return ((a3 * u + a2) * u + a1) * u + a0; };
  const double size = std::abs(a0) + std::abs(a1) + std::abs(a2) + std::abs(a3);
  // Critical points: roots of 3 a3 u^2 + 2 a2 u + a1 in (0, 1), found without dividing by a small a3.
  double breaks[4] = {0.0, 0.0, 0.0, 1.0};
  int count = 1;
  const double qa = 3.0 * a3, qb = 2.0 * a2, qc = a1;
  const double scale = std::abs(qa) + std::abs(qb) + std::abs(qc);
  if (scale > 0.0) {
    double critical[2];
    int found = 0;
    if (std::abs(qa) <= 1e-14 * scale) {
      if (qb != 0.0) critical[found++] = -qc / qb;
    } else {
      const double discriminant = qb * qb - 4.0 * qa * qc;
      if (discriminant >= 0.0) {
        const double q = -0.5 * (qb + std::copysign(std::sqrt(discriminant), qb));
        critical[found++] = q / qa;
        if (q != 0.0) critical[found++] = qc / q;
      }
    }
    std::sort(critical, critical + found);
    for (int i = 0; i < found; ++i)
      if (critical[i] > 0.0 && critical[i] < 1.0) breaks[count++] = critical[i];
  }
  breaks[count++] = 1.0;
  int n = 0;
  double g_previous = g(breaks[0]);
  if (g_previous == 0.0) roots[n++] = 0.0;
  for (int i = 1; i < count && n < 3; ++i) {
    const double g_here = g(breaks[i]);
    if (g_here == 0.0) {
      if (breaks[i] > (n ? roots[n - 1] / t_max : -1.0)) roots[n++] = breaks[i] * t_max;
    } else if (g_previous != 0.0 && (g_here < 0.0) != (g_previous < 0.0)) {
      roots[n++] = bracketed_root(g, breaks[i - 1], breaks[i], g_previous, g_here, size) * t_max;
    }
    g_previous = g_here;
  }
  return n;
}

int sheets_through(const Volume& volume, const glm::dvec3& x, Sheet sheets[3], double t_min) {
  if (x.x < volume.lower.x || x.y < volume.lower.y || x.z < volume.lower.z || x.x > volume.upper.x ||
      x.y > volume.upper.y || x.z > volume.upper.z)
    return 0;
  // det[E1(t), E2(t), x - T0(t)] = (k0 + k1 t + k2 t^2) . (c - t D0), c = x - P0: a cubic in t.
  const glm::dvec3 c = x - volume.origin[0];
  const double c0 = glm::dot(volume.k[0], c);
  const double c1 = glm::dot(volume.k[1], c) - volume.k_dot_d0[0];
  const double c2 = glm::dot(volume.k[2], c) - volume.k_dot_d0[1];
  const double c3 = -volume.k_dot_d0[2];
  double roots[3];
  const int count = cubic_roots(c0, c1, c2, c3, volume.t_max, roots);
  const glm::dvec3 a1 = volume.origin[1] - volume.origin[0], a2 = volume.origin[2] - volume.origin[0];
  const glm::dvec3 b1 = volume.direction[1] - volume.direction[0], b2 = volume.direction[2] - volume.direction[0];
  int found = 0;
  for (int r = 0; r < count; ++r) {
    const double t = roots[r];
    if (t < t_min) continue;
    const glm::dvec3 e1 = a1 + t * b1, e2 = a2 + t * b2, rel = c - t * volume.direction[0];
    const glm::dvec3 normal = glm::cross(e1, e2);
    const double area2 = glm::dot(normal, normal);
    if (!(area2 > 0.0)) continue;  // the cross-section collapsed to a line: no area to be inside
    const double w1 = glm::dot(glm::cross(rel, e2), normal) / area2, w2 = glm::dot(glm::cross(e1, rel), normal) / area2;
    const double w0 = 1.0 - w1 - w2;
    constexpr double kEdge = -1e-9;  // rounding on an edge shared by two volumes
    if (w0 < kEdge || w1 < kEdge || w2 < kEdge) continue;
    sheets[found++] = Sheet{t, {w0, w1, w2}};
  }
  return found;
}

Color beam_irradiance(const Volume& volume, const Sheet& sheet, Intensity intensity) {
  const double t = sheet.t;
  if (intensity == Intensity::constant) {
    // The flux through the triangle spread evenly over the cross-section T(t), measured across the
    // triangle's mean direction: one value per cross-section. At a focus the cross-section vanishes;
    // the floor keeps the value finite (1e4 times the entering irradiance at most), as a pixel's finite
    // area would.
    const Color entering = (volume.arriving[0] + volume.arriving[1] + volume.arriving[2]) * (1.0f / 3.0f);
    const glm::dvec3 section = volume.k[0] + t * volume.k[1] + t * t * volume.k[2];
    const double area_out = 0.5 * std::abs(glm::dot(section, volume.mean_direction));
    return entering * static_cast<float>(volume.area_in / std::max(area_out, 1e-4 * volume.area_in));
  }
  // Each vertex's ray tube (its one-ring: the area it entered across the light, its cross-section at t
  // across its ray, a quadratic in t), the tubes' flux and areas interpolated, the one over the other:
  // continuous across the edges the vertices share. (Interpolating the densities themselves would
  // overstate the light where neighbouring tubes differ by orders of magnitude, as behind a solid's
  // silhouette: the mean of 1 / area exceeds 1 / the mean area.)
  Color flux(0.0f);
  double area_out = 0.0, area_in = 0.0;
  for (int i = 0; i < 3; ++i) {
    const auto& q = volume.ring_area_out[i];
    flux += volume.arriving[i] * static_cast<float>(sheet.weights[i] * volume.ring_area_in[i]);
    area_in += sheet.weights[i] * volume.ring_area_in[i];
    area_out += sheet.weights[i] * std::abs(q[0] + t * (q[1] + t * q[2]));
  }
  return flux * static_cast<float>(1.0 / std::max(area_out, 1e-4 * area_in));
}

Color sheet_irradiance(const Volume& volume, const Sheet& sheet, const glm::dvec3& x, const glm::dvec3& n,
                       Intensity intensity) {
  const auto& w = sheet.weights;
  const glm::dvec3 direction =
      glm::normalize(w[0] * volume.direction[0] + w[1] * volume.direction[1] + w[2] * volume.direction[2]);
  const glm::dvec3 start = w[0] * volume.origin[0] + w[1] * volume.origin[1] + w[2] * volume.origin[2];
  const Color through = glm::exp(-volume.absorption * static_cast<float>(glm::length(x - start)));
  return beam_irradiance(volume, sheet, intensity) * through * static_cast<float>(std::abs(glm::dot(n, direction)));
}

Color volume_irradiance(const Volume& volume, const glm::dvec3& x, const glm::dvec3& n, Intensity intensity,
                        double t_min) {
  Color sum(0.0f);
  Sheet sheets[3];
  const int count = sheets_through(volume, x, sheets, t_min);
  for (int s = 0; s < count; ++s) sum += sheet_irradiance(volume, sheets[s], x, n, intensity);
  return sum;
}

}  // namespace causticbench::caustic_volume
