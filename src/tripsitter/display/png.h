// PNG files (libpng): 8-bit RGB; a 12-bit image has each 4-bit channel expanded as v * 17.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <tripsitter/core/result.h>
#include <tripsitter/core/image.h>
#include <tripsitter/display/io.h>

namespace tripsitter::display {

// Writes the image to `path`. On failure nothing is left at `path` (the file is written beside it and renamed).
core::Result<bool, IoError> write_png(const std::string& path, const core::Image444& image);
core::Result<bool, IoError> write_png(const std::string& path, const core::ImageRgb8& image);

// The bytes of the PNG file write_png would write, in memory (thumbnails embedded in explore's index.html).
core::Result<std::vector<std::uint8_t>, IoError> encode_png(const core::ImageRgb8& image);

// Reads an 8-bit RGB or RGBA PNG back into 12-bit colour (each channel rounded to v / 17), for tests and tools.
core::Result<core::Image444, IoError> read_png(const std::string& path);

}  // namespace tripsitter::display
