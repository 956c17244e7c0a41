// OpenEXR files (Debian's libopenexr-dev): linear half or float channels, with the AOVs as layers, for grading
// and compositing. The image is generic (named channels of floats); the caller decides what the channels hold.
//
// Channel names follow OpenEXR's conventions ("layer.channel"), which compositors read as layers:
//   R, G, B              the beauty, without a layer: the file's main image everywhere (Nuke's rgba; Blender's
//                        Combined pass);
//   <layer>.R/.G/.B      a colour layer, e.g. albedo.R (add_rgb);
//   <layer>.X/.Y/.Z      a vector layer, e.g. normal.X (add_xyz): what Blender writes for its own normal pass
//                        (ViewLayer.Normal.X), and its reader keeps X, Y, Z in that order as it does R, G, B;
//   Z                    depth (add_depth): OpenEXR's standard depth channel, read by Nuke into its depth.Z and
//                        by Blender as its Depth pass. add_depth marks it float, whatever the beauty's type:
//                        half's 11-bit significand leaves steps of 1/16 at a depth of 100 and ends at 65504,
//                        too coarse for defocus or fog. It holds the caller's depth as given (infinity stays).
// Files are scanline images, top row first (INCREASING_Y), data and display windows both (0,0)-(w-1,h-1), with
// ZIP compression (16 scanlines per block): lossless for half and float alike, and Blender's default. PIZ is
// lossless too but made for grainy film scans: on a 640x480 render with AOVs its files were 31-57% larger than
// ZIP's at the same speed; ZIPS (1 scanline per block) was 14-16% larger.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <tripsitter/core/result.h>
#include <tripsitter/core/vec.h>
#include <tripsitter/display/io.h>  // ExrPixel, how a channel's values are stored

namespace tripsitter::display {

struct ExrChannel {
  std::string name;           // unique in the image, not empty (OpenEXR allows up to 255 bytes)
  std::vector<float> values;  // width * height, row-major, top row first
  // The channel's type in the file; unset: the type given to write_exr. read_exr sets it to the file's type
  // (unset for a channel of 32-bit unsigned integers, which it converts to float).
  std::optional<ExrPixel> pixel;
};

struct ExrImage {
  int width = 0;
  int height = 0;
  std::vector<ExrChannel> channels;  // in any order; read_exr gives the file's order (sorted by name)
};

// Appends the channels "<layer>.R", "<layer>.G", "<layer>.B" ("R", "G", "B" when `layer` is empty) from
// interleaved triples: rgb = {r0, g0, b0, r1, g1, b1, ...}, width * height of them for write_exr to accept
// (a trailing partial triple is dropped).
void add_rgb(ExrImage& image, std::string_view layer, std::span<const float> rgb);
// The same with the vector channel names "<layer>.X", "<layer>.Y", "<layer>.Z".
void add_xyz(ExrImage& image, std::string_view layer, std::span<const float> xyz);
// The same from a buffer of vectors (an image's pixels, a feature buffer), one triple each.
void add_rgb(ExrImage& image, std::string_view layer, std::span<const core::Vec3f> rgb);
void add_xyz(ExrImage& image, std::string_view layer, std::span<const core::Vec3f> xyz);
// Appends the depth channel "Z", stored as float whatever write_exr's type.
void add_depth(ExrImage& image, std::span<const float> depth);

// The channel of that name, or nullptr.
const ExrChannel* find_channel(const ExrImage& image, std::string_view name);

// Writes the image to `path`, each channel as its own `pixel` type or else as `pixel`. Fails, with nothing
// written, on an empty image (no pixels or no channels), a channel whose value count is not width * height, or
// a channel name that is empty, repeated or longer than 255 bytes. The file is made in memory and written
// beside `path` and renamed (io.h), so on failure `path` is as it was and no temporary file stays behind.
core::Result<bool, IoError> write_exr(const std::string& path, const ExrImage& image, ExrPixel pixel);

// Reads any scanline or tiled single-part EXR file (its first part if multi-part): the data window becomes the
// image, every channel converted to float (half exactly). Fails with a message naming the path on a missing
// or unreadable file, one that is not EXR or is damaged, a deep image, a subsampled channel, or one of more
// than 2^28 values (pixels times channels). Never throws.
core::Result<ExrImage, IoError> read_exr(const std::string& path);

}  // namespace tripsitter::display
