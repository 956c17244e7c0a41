#include <tripsitter/host/rom_image.h>

#include <cstdio>
#include <stdexcept>

namespace tripsitter::host {
namespace {

void put_number(std::vector<std::uint8_t>& out, std::size_t at, std::size_t value) {
  if (value > UINT32_MAX) throw std::length_error("a ROM image of more than 4 GiB");
  for (std::size_t i = 0; i < kRomNumberBytes; ++i)
    out[at + i] = static_cast<std::uint8_t>(value >> (8 * (kRomNumberBytes - 1 - i)));
}

std::size_t number_at(std::span<const std::uint8_t> image, std::size_t at) {
  std::size_t v = 0;
  for (std::size_t i = 0; i < kRomNumberBytes; ++i) v = (v << 8) | image[at + i];
  return v;
}

}  // namespace

RomImage make_rom_image(Host& host, const CameraPath& path, int worlds, link::Numbering numbering) {
  RomImage rom;
  rom.worlds = static_cast<std::size_t>(worlds);
  const std::size_t table = kRomNumberBytes * (rom.worlds + 2);
  rom.bytes.resize(table);
  put_number(rom.bytes, 0, rom.worlds);
  for (int i = 0; i < worlds; ++i) {
    if (i > 0) step_camera(host.camera(), path, worlds);
    const ReadyWorld& ready = host.update();
    std::vector<std::uint8_t> world = ready.bytes;
    numbering.stamp(world);
    put_number(rom.bytes, kRomNumberBytes * (static_cast<std::size_t>(i) + 1), rom.bytes.size());
    rom.bytes.insert(rom.bytes.end(), world.begin(), world.end());
    rom.spheres = ready.spheres;
    rom.saturations += ready.saturations;
  }
  put_number(rom.bytes, kRomNumberBytes * (rom.worlds + 1), rom.bytes.size());
  return rom;
}

core::Result<std::vector<std::span<const std::uint8_t>>, std::string> rom_worlds(std::span<const std::uint8_t> image) {
  if (image.size() < kRomNumberBytes) return std::string("shorter than the world count");
  const std::size_t count = number_at(image, 0);
  if (count == 0) return std::string("a world count of 0");
  if (count > image.size() / kRomNumberBytes || kRomNumberBytes * (count + 2) > image.size())
    return "a table of " + std::to_string(count) + " worlds does not fit in " + std::to_string(image.size()) + " bytes";
  std::vector<std::span<const std::uint8_t>> worlds;
  std::size_t start = number_at(image, kRomNumberBytes);
  if (start != kRomNumberBytes * (count + 2))
    return "world 0 starts at " + std::to_string(start) + ", not after the table";
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t end = number_at(image, kRomNumberBytes * (k + 2));
    if (end < start || end > image.size())
      return "world " + std::to_string(k) + " ends at " + std::to_string(end) + ", outside " + std::to_string(start) +
             " .. " + std::to_string(image.size());
    worlds.push_back(image.subspan(start, end - start));
    start = end;
  }
  if (start != image.size()) return std::to_string(image.size() - start) + " bytes after the last world";
  return worlds;
}

std::string to_readmemh(std::span<const std::uint8_t> image, const std::vector<std::string>& comments) {
  std::string text;
  for (const std::string& c : comments) text += "// " + c + "\n";
  text.reserve(text.size() + 3 * image.size());
  for (const std::uint8_t b : image) {
    char digits[4];
    std::snprintf(digits, sizeof digits, "%02x\n", b);
    text += digits;
  }
  return text;
}

}  // namespace tripsitter::host
