// The energy prt's band limit loses (issue 35's lost-flux counter, its second part). The transfer of a
// unit-irradiance beam from source direction w holds in the grid a fluence F(w) (volume times the
// radiance integrated over directions, summed over the cells: sqrt(4 pi) V sum l_0, from the build's own
// sums, before any truncation). A lighting L brings the grid the fluence  Phi = integral F(w) L(w) dw.
// The frame's product reproduces the band-limited part: summing the matrices' band-0 rows over the cells
// gives exactly the first sh_order^2 coefficients F_j of F (the same Fibonacci sums), so the field holds
// Phi_band = sum_{j < n^2} F_j L_j with the frame's (windowed) lighting, while the full lighting brings
// Phi_full = sum_j F_j L_j over every band. F is smooth (an integral over the object), so its series is
// taken to as many bands as the N source directions resolve (sqrt(N / 2), at most kMaxBands, the largest
// the SH machinery holds: 10 from 200 directions; the share of F's norm in its top band is reported beside
// it), and the full lighting is projected to as many. Where that is no more than sh_order, the loss cannot
// be told from the build and is reported unknown. What the band limit misplaces inside the grid
// (blur, ringing) is not lost energy: that is what the metrics measure.
#pragma once

#include <vector>

#include "core/math.h"

namespace causticbench::prt {

// F's coefficients per colour, at response_bands(N) bands, from its values at the build's source directions
// (the spherical Fibonacci lattice of N = `responses.size() / 3` points, weights 4 pi / N). `responses`:
// per direction 3 values (r, g, b).
int response_bands(int source_directions);
struct ResponseHarmonics {
  int bands = 0;
  std::vector<double> coefficients[3];  // bands^2 each
  double top_band_share = 0.0;  // the share of F's squared norm in its top band (how well kMaxBands bands hold it)
};
ResponseHarmonics response_harmonics(const std::vector<double>& responses);

struct BandLimitEnergy {
  double full = 0.0;          // Phi_full: the full lighting's fluence in the grid
  double band_limited = 0.0;  // Phi_band: what the frame's product holds
  // The share of Phi_full the band limit loses (negative: it adds, as a truncated delta can).
  double change() const { return full > 0.0 ? (full - band_limited) / full : 0.0; }
};

// From the response, the frame's lighting as the product used it (per colour `bands`^2 floats, windowed)
// and the same lighting projected unwindowed to response.bands bands (per colour response.bands^2).
BandLimitEnergy band_limit_energy(const ResponseHarmonics& response, int bands, const std::vector<float>& used,
                                  const std::vector<double> full[3]);

}  // namespace causticbench::prt
