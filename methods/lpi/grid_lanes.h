// lpi's grid lookup for eight receiver points at once (issue 11's lookup rate): the per-pixel work of
// lookup.h (map into build space, the grid's trilinear stencil, the reads of the light samples, the
// shading) computed in AVX2 lanes, one receiver point a lane, the stored values fetched with gathers
// (float32: four-float loads turned into lanes; float16 converted by F16C).
// Every lane does the scalar code's IEEE operations in the scalar code's order (no FMA, no
// reassociation), so the image is bit for bit the scalar lookup's (test_lpi_fast_paths.cpp checks
// it). Taken where the processor has AVX2 and every read of the object is unrotated (nearest and
// barycentric blends, environment lights' combined volume); everything else, and processors without
// AVX2 or F16C, stay on the scalar lookup (add_object_caustic_scalar).
#pragma once

#include <cstddef>
#include <vector>

#include "core/gbuffer.h"
#include "core/image.h"
#include "methods/common/grid_layout.h"
#include "methods/common/stored_values.h"

namespace causticbench::lpi {

struct ObjectView;

// Whether add_grid_caustic_lanes takes this object: AVX2 and F16C present, CAUSTICBENCH_LPI_SCALAR_LOOKUP not
// set, a grid of resolution 2 or more, 3 or 9 channels, no spherical harmonics, no rotated read, and
// stored values small enough for 32-bit gather offsets.
bool grid_lanes_apply(const GridLayout& layout, const ObjectView& view);

// add_object_caustic for pixels [begin, end) in lanes; only where grid_lanes_apply() is true.
void add_grid_caustic_lanes(const GridLayout& layout, const ObjectView& view, const GBuffer& gbuffer, size_t begin,
                            size_t end, Image& result);

// Every value of one light sample decoded through the lanes' gathers (the decoding alone, for
// test_lpi_fast_paths.cpp to hold against StoredDecoding::value); false without AVX2 or for channel
// counts other than 3 and 9.
bool decode_in_lanes(const StoredValues& values, size_t light_sample, std::vector<float>& decoded);

}  // namespace causticbench::lpi
