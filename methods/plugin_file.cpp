#include "methods/plugin_file.h"

#include <elf.h>

#include <cstring>
#include <fstream>
#include <vector>

#include <fmt/format.h>

namespace causticbench {

namespace {

// Reads `count` bytes at `offset` into `out`; false when the file ends first.
bool read_at(std::ifstream& file, uint64_t offset, void* out, size_t count) {
  file.clear();
  file.seekg(static_cast<std::streamoff>(offset));
  file.read(static_cast<char*>(out), static_cast<std::streamsize>(count));
  return static_cast<size_t>(file.gcount()) == count;
}

}  // namespace

std::string plugin_file_problem(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return "it cannot be opened";
  file.seekg(0, std::ios::end);
  const uint64_t size = static_cast<uint64_t>(file.tellg());
  Elf64_Ehdr header{};
  if (!read_at(file, 0, &header, sizeof header) || std::memcmp(header.e_ident, ELFMAG, SELFMAG) != 0)
    return fmt::format("it is not an ELF shared library ({} bytes, no ELF header)", size);
  if (header.e_ident[EI_CLASS] != ELFCLASS64 || header.e_ident[EI_DATA] != ELFDATA2LSB || header.e_machine != EM_X86_64)
    return "it is an ELF file for another machine (expected 64-bit x86-64)";
  if (header.e_type != ET_DYN) return "it is an ELF file but not a shared library (build it with add_library(... MODULE))";
  auto beyond = [&](uint64_t offset, uint64_t count, uint64_t entry) {
    return entry != 0 && (count > size / entry || offset > size - count * entry);
  };
  if (header.e_phentsize != sizeof(Elf64_Phdr) || header.e_phnum == 0 ||
      beyond(header.e_phoff, header.e_phnum, header.e_phentsize))
    return fmt::format("it is {} bytes, but its program headers lie beyond that: the file is truncated or damaged", size);
  if (header.e_shnum != 0 && beyond(header.e_shoff, header.e_shnum, header.e_shentsize))
    return fmt::format("it is {} bytes, but its section headers end at byte {}: the file is truncated", size,
                       header.e_shoff + uint64_t(header.e_shnum) * header.e_shentsize);
  std::vector<Elf64_Phdr> segments(header.e_phnum);
  if (!read_at(file, header.e_phoff, segments.data(), segments.size() * sizeof(Elf64_Phdr)))
    return "its program headers cannot be read: the file is truncated";
  for (size_t s = 0; s < segments.size(); ++s) {
    const Elf64_Phdr& segment = segments[s];
    if (segment.p_filesz == 0) continue;
    if (segment.p_offset > size || segment.p_filesz > size - segment.p_offset)
      return fmt::format("it is {} bytes, but its segment {} ends at byte {}: the file is truncated", size, s,
                         segment.p_offset + segment.p_filesz);
  }
  return "";
}

}  // namespace causticbench
