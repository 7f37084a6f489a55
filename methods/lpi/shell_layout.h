// `storage: shells` (Wyman 2003, Section 4.2): concentric shells around the object's centre, each
// sampled at the vertices of a geodesic sphere (an icosahedron subdivided `shell_subdivision` times),
// the angular cell of a direction found by a table lookup (SphericalMesh::locate).
//
// Samples sit at the vertices, not in the faces: the paper's Fig. 11 sizes per light sample (5.7,
// 22.5, 90.1, 360, 1440 KB) are exactly 12 shells x (10 4^s + 2) vertices x 3 bytes, in KiB, for s = 2 .. 6.
//
// A sample's value is the irradiance weighted by its interpolation basis function: B = (gnomonic
// barycentric weight within each face at the vertex) x (radial hat between neighbouring shells).
// The basis functions sum to one everywhere in the ball, so the estimator
//   value_v = sum over track pieces of P l B_v / integral of B_v dV
// reproduces a uniform field exactly in expectation, and interpolating with the same B reads back
// what was deposited. Track pieces are cut exactly at shell spheres and face planes; along each
// piece B_v is integrated by two-point Gauss-Legendre quadrature (B is smooth inside a piece).
#pragma once

#include <array>
#include <vector>

#include "methods/common/geodesic.h"
#include "methods/common/volume_layout.h"

namespace causticbench::lpi {

// uniform: r_k = R (k + 1) / K; quadratic: r_k = R ((k + 1) / K)^2, denser near the object, where its
// caustics focus and vary fastest.
enum class ShellSpacing { uniform, quadratic };

class ShellLayout final : public VolumeLayout {
 public:
  ShellLayout(Vec3 center, float radius, int shell_count, int subdivision, ShellSpacing spacing);
  size_t points() const override { return radii_.size() * directions(); }
  void deposit(const PathSegment& segment, Orientation orientation, float* sums) const override;
  void normalise(double photons_emitted, Orientation orientation, double* values) const override;
  Stencil stencil(const Vec3& position) const override;
  size_t memory_bytes() const override;

  const std::vector<float>& radii() const { return radii_; }
  size_t directions() const { return mesh_.points().size(); }
  const SphericalMesh& mesh() const { return mesh_; }
  // integral over the sphere of vertex v's angular basis function (they sum to 4 pi).
  const std::vector<double>& angular_integrals() const { return angular_integral_; }
  // integral of shell k's radial hat times r^2 dr.
  const std::vector<double>& radial_integrals() const { return radial_integral_; }

 private:
  // The radial interval of distance r: k such that r_{k-1} <= r < r_k (r_{-1} = 0); K when r >= R.
  int radial_interval(float r) const;
  void add_piece(const PathSegment& segment, const Vec3& offset_origin, float t0, float t1, uint32_t triangle,
                 Orientation orientation, float* sums) const;

  SphericalMesh mesh_;
  std::vector<float> radii_;
  std::vector<double> angular_integral_;
  std::vector<double> radial_integral_;
};

}  // namespace causticbench::lpi
