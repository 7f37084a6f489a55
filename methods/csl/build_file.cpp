#include "methods/csl/build_file.h"

#include <cstring>
#include <fstream>
#include <stdexcept>
#include <type_traits>

#include "core/files.h"

namespace causticbench::csl {

namespace {

// 2: Fit::failed (issue 30). 3: SpotLightSet::misdirected_energy (issue 52). A build of an earlier format is
// unreadable to this version: the build cache computes it again, with its warning.
constexpr char kFormat[] = "causticbench csl build 3";

// Writes into the stream of the store's atomic write (core/files.h, write_stream_atomically), which checks
// it and names the OS error of a failed write.
class Writer {
 public:
  explicit Writer(std::ostream& stream) : stream_(stream) {}
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    stream_.write(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  template <class T>
  void list(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    value<uint64_t>(values.size());
    stream_.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(values.size() * sizeof(T)));
  }
  void bytes(const char* data, size_t size) { stream_.write(data, static_cast<std::streamsize>(size)); }

 private:
  std::ostream& stream_;
};

class Reader {
 public:
  explicit Reader(const std::string& path) : path_(path), stream_(path, std::ios::binary) {
    if (!stream_) fail("cannot be opened");
  }
  template <class T>
  T value() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v{};
    stream_.read(reinterpret_cast<char*>(&v), sizeof(T));
    if (!stream_) fail("truncated");
    return v;
  }
  template <class T>
  std::vector<T> list() {
    const uint64_t count = value<uint64_t>();
    if (count > (uint64_t{1} << 32)) fail("an implausible count");
    std::vector<T> values(count);
    stream_.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(count * sizeof(T)));
    if (!stream_) fail("truncated");
    return values;
  }
  void bytes(char* data, size_t size) {
    stream_.read(data, static_cast<std::streamsize>(size));
    if (!stream_) fail("truncated");
  }
  [[noreturn]] void fail(const std::string& what) const { throw std::runtime_error(path_ + ": " + what); }
  bool at_end() { return stream_.peek() == std::char_traits<char>::eof(); }

 private:
  std::string path_;
  std::ifstream stream_;
};

void write_light(Writer& out, const SpotLight& light) {
  out.value(light.origin);
  out.value(light.axis);
  out.value(light.u);
  out.value(light.v);
  out.value(light.profile.kappa);
  out.value(light.profile.beta);
  out.value<uint8_t>(light.adds ? 1 : 0);
  const IntensityImage& image = light.image;
  out.value<int32_t>(image.size());
  out.value<int32_t>(image.channels());
  out.value(image.half_size());
  out.value<uint8_t>(image.precision() == IntensityImage::Precision::uint16 ? 1 : 0);
  out.list(image.floats());
  out.list(image.quantised());
  out.list(image.scales());
}

SpotLight read_light(Reader& in) {
  SpotLight light;
  light.origin = in.value<Vec3>();
  light.axis = in.value<Vec3>();
  light.u = in.value<Vec3>();
  light.v = in.value<Vec3>();
  light.profile.kappa = in.value<double>();
  light.profile.beta = in.value<double>();
  light.adds = in.value<uint8_t>() != 0;
  const int32_t size = in.value<int32_t>(), channels = in.value<int32_t>();
  const float half = in.value<float>();
  const auto precision = in.value<uint8_t>() ? IntensityImage::Precision::uint16 : IntensityImage::Precision::float32;
  std::vector<float> floats = in.list<float>();
  std::vector<uint16_t> quantised = in.list<uint16_t>();
  std::vector<float> scales = in.list<float>();
  try {
    light.image = IntensityImage::from_stored(size, channels, half, precision, std::move(floats), std::move(quantised),
                                              std::move(scales));
  } catch (const std::invalid_argument& error) {
    in.fail(error.what());
  }
  return light;
}

void write_set(Writer& out, const SpotLightSet& set) {
  out.value(set.direction);
  out.value(set.ray_energy);
  out.value(set.covered_energy);
  out.value(set.misdirected_energy);
  out.value<int32_t>(set.rays);
  out.value<int32_t>(set.seeds_tried);
  out.value(set.trace_seconds);
  out.value(set.cluster_seconds);
  out.value<uint64_t>(set.lights.size());
  for (const SpotLight& light : set.lights) write_light(out, light);
  // The records are plain numbers; SpotLightRecord is trivially copyable.
  out.list(set.records);
}

SpotLightSet read_set(Reader& in) {
  SpotLightSet set;
  set.direction = in.value<Vec3>();
  set.ray_energy = in.value<double>();
  set.covered_energy = in.value<double>();
  set.misdirected_energy = in.value<double>();
  set.rays = in.value<int32_t>();
  set.seeds_tried = in.value<int32_t>();
  set.trace_seconds = in.value<double>();
  set.cluster_seconds = in.value<double>();
  const uint64_t lights = in.value<uint64_t>();
  if (lights > 100000) in.fail("an implausible number of spot lights");
  for (uint64_t i = 0; i < lights; ++i) set.lights.push_back(read_light(in));
  set.records = in.list<SpotLightRecord>();
  if (set.records.size() != set.lights.size()) in.fail("records and spot lights differ in number");
  return set;
}

void write_dynamic(Writer& out, const DynamicSets& dynamic) {
  out.value<int32_t>(dynamic.level);
  out.list(dynamic.vertices);
  out.value<uint64_t>(dynamic.sets.size());
  for (size_t s = 0; s < dynamic.sets.size(); ++s) {
    write_set(out, dynamic.sets[s]);
    out.value<uint64_t>(dynamic.black[s].size());
    for (const SpotLight& light : dynamic.black[s]) write_light(out, light);
  }
  out.value<uint64_t>(dynamic.edges.size());
  for (const DynamicSets::Edge& edge : dynamic.edges) {
    out.value(edge.first);
    out.value(edge.second);
    out.list(edge.pairs);
    const int32_t counts[4] = {edge.matched, edge.black_first, edge.black_second, edge.tracked_lost};
    out.value(counts);
    out.value(edge.mean_distance);
    out.value(edge.seconds);
  }
  out.value<uint64_t>(dynamic.facets.size());
  for (const DynamicSets::Facet& facet : dynamic.facets) {
    out.value(facet.triangle);
    out.value(facet.sets);
    out.list(facet.triples);
  }
}

DynamicSets read_dynamic(Reader& in) {
  DynamicSets dynamic;
  dynamic.level = in.value<int32_t>();
  dynamic.vertices = in.list<uint32_t>();
  const uint64_t sets = in.value<uint64_t>();
  if (sets != dynamic.vertices.size()) in.fail("sets and directions differ in number");
  dynamic.black.resize(sets);
  for (uint64_t s = 0; s < sets; ++s) {
    dynamic.sets.push_back(read_set(in));
    const uint64_t black = in.value<uint64_t>();
    if (black > 1000000) in.fail("an implausible number of black spot lights");
    for (uint64_t i = 0; i < black; ++i) dynamic.black[s].push_back(read_light(in));
  }
  auto check_light = [&](uint32_t set, int32_t index) {
    if (set >= dynamic.sets.size() ||
        (index >= 0 && static_cast<size_t>(index) >= dynamic.sets[set].lights.size() + dynamic.black[set].size())) {
      in.fail("a pair or triple names a spot light that is not stored");
    }
  };
  const uint64_t edges = in.value<uint64_t>();
  for (uint64_t e = 0; e < edges; ++e) {
    DynamicSets::Edge edge;
    edge.first = in.value<uint32_t>();
    edge.second = in.value<uint32_t>();
    edge.pairs = in.list<std::array<int32_t, 2>>();
    for (const auto& pair : edge.pairs) {
      check_light(edge.first, pair[0]);
      check_light(edge.second, pair[1]);
    }
    const auto counts = in.value<std::array<int32_t, 4>>();
    edge.matched = counts[0], edge.black_first = counts[1], edge.black_second = counts[2], edge.tracked_lost = counts[3];
    edge.mean_distance = in.value<double>();
    edge.seconds = in.value<double>();
    dynamic.edges.push_back(std::move(edge));
  }
  const uint64_t facets = in.value<uint64_t>();
  for (uint64_t f = 0; f < facets; ++f) {
    DynamicSets::Facet facet;
    facet.triangle = in.value<uint32_t>();
    facet.sets = in.value<std::array<uint32_t, 3>>();
    facet.triples = in.list<Triple>();
    for (const Triple& triple : facet.triples) {
      for (int c = 0; c < 3; ++c) check_light(facet.sets[c], triple.light[c]);
    }
    dynamic.facets.push_back(std::move(facet));
  }
  return dynamic;
}

}  // namespace

void write_object_build(const std::string& path, const ObjectBuild& build) {
  write_stream_atomically(path, [&](std::ostream& stream) {
    Writer out(stream);
    out.bytes(kFormat, sizeof(kFormat));
    out.value<uint8_t>(build.dynamic ? 1 : 0);
    if (build.dynamic) {
      write_dynamic(out, *build.dynamic);
    } else {
      out.value<uint64_t>(build.sets.size());
      for (const SpotLightSet& set : build.sets) write_set(out, set);
    }
  });
}

ObjectBuild read_object_build(const std::string& path) {
  Reader in(path);
  char format[sizeof(kFormat)] = {};
  in.bytes(format, sizeof(format));
  if (std::memcmp(format, kFormat, sizeof(kFormat)) != 0) in.fail(std::string("not a build of format '") + kFormat + "'");
  ObjectBuild build;
  if (in.value<uint8_t>()) {
    build.dynamic = read_dynamic(in);
  } else {
    const uint64_t sets = in.value<uint64_t>();
    if (sets > 100000) in.fail("an implausible number of sets");
    for (uint64_t s = 0; s < sets; ++s) build.sets.push_back(read_set(in));
  }
  if (!in.at_end()) in.fail("bytes after the build");
  return build;
}

}  // namespace causticbench::csl
