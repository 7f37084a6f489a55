#include "core/low_discrepancy.h"

#include <algorithm>
#include <stdexcept>

#include "core/sampling.h"

namespace causticbench {

namespace {

// Direction numbers v_k (k = 1..32, stored at k - 1) of one dimension, from its primitive polynomial of
// degree s with inner coefficients a (Joe & Kuo 2008, new-joe-kuo-6.21201, dimensions 2 to 8) and
// initial m_1..m_s (Bratley & Fox 1988's recurrence).
struct SobolDimension {
  int degree;
  uint32_t coefficients;
  std::array<uint32_t, 5> initial;
};

constexpr std::array<SobolDimension, kSobolDimensions - 1> kParameters = {{
    {1, 0, {1}},
    {2, 1, {1, 3}},
    {3, 1, {1, 3, 1}},
    {3, 2, {1, 1, 1}},
    {4, 1, {1, 1, 3, 3}},
    {4, 4, {1, 3, 5, 13}},
    {5, 2, {1, 1, 5, 5, 17}},
}};

using DirectionNumbers = std::array<std::array<uint32_t, 32>, kSobolDimensions>;

DirectionNumbers make_direction_numbers() {
  DirectionNumbers v{};
  for (int k = 0; k < 32; ++k) v[0][k] = 1u << (31 - k);
  for (int d = 1; d < kSobolDimensions; ++d) {
    const SobolDimension& p = kParameters[static_cast<size_t>(d - 1)];
    const int s = p.degree;
    for (int k = 0; k < s; ++k) v[d][k] = p.initial[static_cast<size_t>(k)] << (31 - k);
    for (int k = s; k < 32; ++k) {
      uint32_t value = v[d][k - s] ^ (v[d][k - s] >> s);
      for (int j = 1; j < s; ++j)
        if ((p.coefficients >> (s - 1 - j)) & 1u) value ^= v[d][k - j];
      v[d][k] = value;
    }
  }
  return v;
}

// The product of a dimension's generator matrix with each byte of the index, per byte position: a point
// is then four lookups XORed (the photon tracer draws seven a photon, so the bit loop's 20-odd steps per
// dimension cost more than tracing a ray does).
using ByteTables = std::array<std::array<std::array<uint32_t, 256>, 4>, kSobolDimensions>;

ByteTables make_byte_tables() {
  const DirectionNumbers v = make_direction_numbers();
  ByteTables tables{};
  for (int d = 0; d < kSobolDimensions; ++d)
    for (int position = 0; position < 4; ++position)
      for (uint32_t byte = 0; byte < 256; ++byte) {
        uint32_t bits = 0;
        for (int k = 0; k < 8; ++k)
          if (byte & (1u << k)) bits ^= v[static_cast<size_t>(d)][static_cast<size_t>(8 * position + k)];
        tables[static_cast<size_t>(d)][static_cast<size_t>(position)][byte] = bits;
      }
  return tables;
}

const ByteTables kByteTables = make_byte_tables();

}  // namespace

uint32_t sobol_bits(uint32_t index, int dimension) {
  if (dimension < 0 || dimension >= kSobolDimensions) throw std::out_of_range("Sobol dimension out of range");
  const auto& tables = kByteTables[static_cast<size_t>(dimension)];
  return tables[0][index & 0xffu] ^ tables[1][(index >> 8) & 0xffu] ^ tables[2][(index >> 16) & 0xffu] ^
         tables[3][index >> 24];
}

ShiftedSobol::ShiftedSobol(uint64_t seed, uint64_t pass) {
  // A generator of its own, apart from the photons' Random(seed, index): its seed is (seed) mixed by
  // splitmix64's finaliser, its stream the pass.
  uint64_t mixed = seed + 0x9e3779b97f4a7c15ull;
  mixed = (mixed ^ (mixed >> 30)) * 0xbf58476d1ce4e5b9ull;
  mixed = (mixed ^ (mixed >> 27)) * 0x94d049bb133111ebull;
  mixed ^= mixed >> 31;
  Random random(mixed, pass);
  for (uint32_t& shift : shift_) shift = random.next();
}

float ShiftedSobol::uniform(uint32_t index, int dimension) const {
  const uint32_t bits = sobol_bits(index, dimension) ^ shift_[static_cast<size_t>(dimension)];
  return static_cast<float>(bits >> 8) * 0x1p-24f;
}

double ShiftedSobol::uniform_double(uint32_t index, int dimension) const {
  const uint32_t bits = sobol_bits(index, dimension) ^ shift_[static_cast<size_t>(dimension)];
  return static_cast<double>(bits) * 0x1p-32;
}

}  // namespace causticbench
