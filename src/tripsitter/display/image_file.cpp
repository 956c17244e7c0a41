// An image file's format chosen by its name (io.h): PNG, or OpenEXR with the feature buffers as layers.
#include <algorithm>
#include <cctype>
#include <filesystem>

#include <tripsitter/display/exr.h>
#include <tripsitter/display/io.h>
#include <tripsitter/display/png.h>

namespace tripsitter::display {
namespace {

// Linear light as traced, the feature buffers present as layers.
ExrImage exr_image(const ImageLayers& layers) {
  ExrImage image{layers.linear.width, layers.linear.height, {}};
  add_rgb(image, "", layers.linear.pixels);
  if (!layers.albedo.empty()) add_rgb(image, "albedo", layers.albedo);
  if (!layers.normal.empty()) add_xyz(image, "normal", layers.normal);
  if (!layers.depth.empty()) add_depth(image, layers.depth);
  return image;
}

}  // namespace

bool is_exr(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".exr";
}

core::Result<bool, IoError> write_image(const std::string& path, const ImageLayers& layers, ExrPixel pixel) {
  return is_exr(path) ? write_exr(path, exr_image(layers), pixel) : write_png(path, layers.rgb);
}

}  // namespace tripsitter::display
