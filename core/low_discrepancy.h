// Randomised quasi-Monte Carlo points for the caustic photon tracer's emission (the reference's
// `emission: stratified`): the first dimensions of Sobol's sequence, each randomised by its own random
// digital shift (an XOR with a uniform 32-bit word). A digitally shifted point is exactly uniform on the
// 2^-32 grid, whatever the shift, so an estimate from it is unbiased, while the shift keeps the
// sequence's stratification: every prefix of 2^m points is still a (t, m, s)-net, so the points of a pass
// fill the emission disk evenly instead of clumping as independent draws do. Independent shifts make
// independent replicates: the spread between passes measures the variance of their mean.
// Why our own code: no Debian package provides Sobol points; the generator is 40 lines.
#pragma once

#include <array>
#include <cstdint>

namespace causticbench {

// Dimensions available (Joe & Kuo's direction numbers for the first ones).
constexpr int kSobolDimensions = 8;

// The index-th point of Sobol's sequence in `dimension` (0-based; 0 is van der Corput's radical inverse),
// as 32 fractional bits.
uint32_t sobol_bits(uint32_t index, int dimension);

// One pass's randomised points: Sobol's sequence with a random digital shift per dimension drawn from
// (seed, pass).
class ShiftedSobol {
 public:
  ShiftedSobol(uint64_t seed, uint64_t pass);
  // Uniform in [0, 1), 24 bits (as Random::uniform), and 32 bits (as Random::uniform_double, to 2^-32).
  float uniform(uint32_t index, int dimension) const;
  double uniform_double(uint32_t index, int dimension) const;

 private:
  std::array<uint32_t, kSobolDimensions> shift_{};
};

}  // namespace causticbench
