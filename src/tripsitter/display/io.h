// The display's error value for files it writes and reads (PNG, EXR, VCD, video), the one way it writes a whole
// file so that a failure leaves nothing half written, and the one place an image file's format is chosen: by its
// name, PNG or OpenEXR (png.h, exr.h).
#pragma once

#include <span>
#include <string>

#include <tripsitter/core/image.h>
#include <tripsitter/core/result.h>
#include <tripsitter/core/vec.h>

namespace tripsitter::display {

struct IoError {
  std::string message;  // names the path and what went wrong
};

// Writes `bytes` to a new file beside `path` ("<path>.tmp-XXXXXXXX", created exclusively) and renames it onto
// `path`, so `path` is either as it was or the whole of `bytes`, and no temporary file stays behind. The error
// reads "<what> '<path>': <reason>".
core::Result<bool, IoError> write_file_beside_and_rename(const std::string& path, std::span<const char> bytes,
                                                         const std::string& what);

// How an OpenEXR channel's values are stored in the file (exr.h).
//   kHalf   16-bit half: each value rounded to the nearest half (ties to even, as Imath::half does); infinities
//           and NaN stay so, and a finite value beyond half's range (|v| >= 65520) becomes infinity of its sign.
//   kFloat  32-bit float: every bit pattern exactly, NaN payloads, -0 and denormals included.
enum class ExrPixel { kHalf, kFloat };

// Whether `path` names an OpenEXR file (.exr, any case); write_image writes any other name as PNG.
bool is_exr(const std::string& path);

// A float renderer's picture as an image file takes it: a PNG file the sRGB-encoded picture; an OpenEXR file
// the linear light as R, G, B and the feature buffers as the layers albedo.R/G/B, normal.X/Y/Z and Z (exr.h),
// each left out when empty. All of width x height pixels, row-major.
struct ImageLayers {
  const core::ImageRgb8& rgb;
  const core::ImageRgbF& linear;
  std::span<const core::Vec3f> albedo = {};
  std::span<const core::Vec3f> normal = {};
  std::span<const float> depth = {};
};

// Writes the layers to `path`: OpenEXR with `pixel` channels (depth always float) for a .exr name, else PNG.
core::Result<bool, IoError> write_image(const std::string& path, const ImageLayers& layers, ExrPixel pixel);

}  // namespace tripsitter::display
