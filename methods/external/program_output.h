// What external's program hands back, checked before anything of it is measured: the E_c image (an EXR
// of the G-buffer's size, R, G, B finite and non-negative) and the optional statistics file.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/image.h"

namespace causticbench {

// What a program's image may hold: R, G, B and at most this many channels in all; and so at most
// program_image_most_bytes() in its file (uncompressed 32-bit floats, with 1 MiB for its header and offset
// tables): a larger file, or a header that claims another size, is refused before its pixels are read.
constexpr int kProgramImageMostChannels = 16;
double program_image_most_bytes(int width, int height);
// The largest statistics file read (a few numbers need far less).
constexpr uintmax_t kProgramStatisticsMostBytes = 4u << 20;

// The program's E_c (its R, G, B channels). Throws std::runtime_error saying what is wrong: no file, not a
// readable EXR, another size, fewer than three channels, or the first pixel that is not finite or is
// negative, with its coordinates and channel.
Image read_program_image(const std::string& path, int width, int height);

// The statistics file, when the program wrote one:
//   {"time_ms": 12.5,                         its own time for the frame (the counter reported_ms)
//    "timings_ms": {"trace": 8.1, ...},       any named timings, milliseconds
//    "counters": {"photons": 100000, ...}}    any named counts
// every key optional, every value a finite number >= 0. Nothing when there is no file; std::runtime_error
// naming the key when it is not JSON, has an unknown key or a value that is not such a number.
std::optional<nlohmann::json> read_program_statistics(const std::string& path);

}  // namespace causticbench
