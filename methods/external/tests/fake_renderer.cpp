// A stand-in for a user's renderer, for tests/test_external.cpp: writes the E_c image external reads back,
// well formed or with one defect at a time.
//   fake_renderer MODE OUT WIDTH HEIGHT [VALUE] [STATS]
//   constant       every pixel VALUE; with STATS, {"time_ms": VALUE, "counters": {"value": VALUE}}
//   nan            a NaN at pixel (1, 2)
//   negative       -0.5 at pixel (0, 0)
//   wrong_size     (WIDTH + 1) x HEIGHT
//   bad_statistics a good image, and STATS holding {"time_ms": "fast"}
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "core/image.h"

int main(int argc, char** argv) {
  using causticbench::Image;
  if (argc < 5) {
    std::fprintf(stderr, "usage: fake_renderer MODE OUT WIDTH HEIGHT [VALUE] [STATS]\n");
    return 2;
  }
  const std::string mode = argv[1], out = argv[2];
  const int width = std::stoi(argv[3]), height = std::stoi(argv[4]);
  const float value = argc > 5 ? std::stof(argv[5]) : 1.0f;
  const std::string statistics = argc > 6 ? argv[6] : "";
  Image image(mode == "wrong_size" ? width + 1 : width, height, 3, value);
  if (mode == "nan") image.at(2 * width + 1, 1) = std::nanf("");
  if (mode == "negative") image.at(0, 0) = -0.5f;
  causticbench::write_exr(image, out);
  if (!statistics.empty()) {
    std::ofstream file(statistics);
    if (mode == "bad_statistics") file << R"({"time_ms": "fast"})";
    else file << "{\"time_ms\": " << value << ", \"counters\": {\"value\": " << value << "}}";
  }
  std::fprintf(stderr, "fake_renderer %s wrote %s\n", mode.c_str(), out.c_str());
  return 0;
}
