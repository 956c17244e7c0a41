// The ROM image of a board that draws without its microcontroller (the report's devkit set-up, its section 5;
// rtl/boards/, docs/rtl.md "The board"): the worlds of a camera path as the host encodes them, each a whole frame as
// the link carries it and numbered as the link numbers them, behind a table that says where each one starts. The
// board's ROM host (rtl/boards/ts_rom_host.sv) sends world k through the device's SPI pins.
//
// Layout, every number a big-endian u32:
//   offset 0          K, the number of worlds (at least 1)
//   offset 4 + 4 k    where world k starts, for k = 0 .. K - 1; at 4 + 4 K, where the last one ends
//   after the table   the worlds, one after another, in the order of the path
// So world k is the bytes [start(k), start(k + 1)). Every offset is below the image's size, which the board's block
// RAM must hold (kBoardRomBytes for rtl/boards/arty_a7/ts_arty_top.sv).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <tripsitter/core/result.h>
#include <tripsitter/host/camera_path.h>
#include <tripsitter/host/host.h>
#include <tripsitter/link/sequence.h>

namespace tripsitter::host {

// The block RAM that ts_arty_top's ROM host holds (its ROM_BYTES): 2 RAMB36. board_rtl_test holds them equal.
inline constexpr std::size_t kBoardRomBytes = 8192;

inline constexpr std::size_t kRomNumberBytes = 4;  // the count and each offset

struct RomImage {
  std::vector<std::uint8_t> bytes;  // the layout above
  std::size_t worlds = 0;
  std::size_t spheres = 0;  // in each world (the scene's, up to the device's scene memory)
  Saturations saturations;  // over every world
};

// The image of `worlds` worlds of `host`'s scene along `path`, from its camera as it stands, each encoded by the host
// and numbered by `numbering`. REQUIRES worlds >= 1.
RomImage make_rom_image(Host& host, const CameraPath& path, int worlds, link::Numbering numbering);

// The worlds of an image, in order; the error says what in the table does not hold.
core::Result<std::vector<std::span<const std::uint8_t>>, std::string> rom_worlds(std::span<const std::uint8_t> image);

// The image as $readmemh reads it: a "// " line for each comment, then one byte a line as two hexadecimal digits.
std::string to_readmemh(std::span<const std::uint8_t> image, const std::vector<std::string>& comments);

}  // namespace tripsitter::host
