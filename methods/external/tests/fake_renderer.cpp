// A stand-in for a user's renderer, for tests/test_external.cpp: writes the E_c image external reads back,
// well formed or with one defect at a time.
//   fake_renderer MODE OUT WIDTH HEIGHT [VALUE] [STATS]
//   constant       every pixel VALUE; with STATS, {"time_ms": VALUE, "counters": {"value": VALUE}}
//   nan            a NaN at pixel (1, 2)
//   negative       -0.5 at pixel (0, 0)
//   wrong_size     (WIDTH + 1) x HEIGHT
//   bad_statistics a good image, and STATS holding {"time_ms": "fast"}
//   huge_header    a WIDTH x HEIGHT EXR whose header claims 12000 x 12000 pixels (1.7 GB of floats), followed by
//                  256 KiB of zeros, so that its offset table can be read: 270 KB in all
//   oversized      2 MiB of bytes that are no EXR (more than any EXR of a small G-buffer can be)
#include <cmath>
#include <cstdint>
#include <iterator>
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
  if (mode == "oversized") {
    std::ofstream(out, std::ios::binary) << std::string(2u << 20, 'x');
    return 0;
  }
  Image image(mode == "wrong_size" ? width + 1 : width, height, 3, value);
  if (mode == "nan") image.at(2 * width + 1, 1) = std::nanf("");
  if (mode == "negative") image.at(0, 0) = -0.5f;
  causticbench::write_exr(image, out);
  if (mode == "huge_header") {
    // The data and display windows (box2i: xMin, yMin, xMax, yMax) made 40000 x 40000; the pixels stay.
    std::fstream file(out, std::ios::in | std::ios::out | std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    for (const std::string name : {"dataWindow", "displayWindow"}) {
      const std::string attribute = name + std::string(1, '\0') + "box2i" + std::string(1, '\0');
      const size_t at = bytes.find(attribute);
      if (at == std::string::npos) return 3;
      const int32_t window[4] = {0, 0, 11999, 11999};
      file.seekp(static_cast<std::streamoff>(at + attribute.size() + 4));
      file.write(reinterpret_cast<const char*>(window), sizeof window);
    }
    file.seekp(0, std::ios::end);
    file << std::string(256u << 10, '\0');
  }
  if (!statistics.empty()) {
    std::ofstream file(statistics);
    if (mode == "bad_statistics") file << R"({"time_ms": "fast"})";
    else file << "{\"time_ms\": " << value << ", \"counters\": {\"value\": " << value << "}}";
  }
  std::fprintf(stderr, "fake_renderer %s wrote %s\n", mode.c_str(), out.c_str());
  return 0;
}
