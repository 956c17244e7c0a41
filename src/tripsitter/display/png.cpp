// PNG through libpng's simplified API (png_image), which reports errors in the struct instead of longjmp. Files and
// in-memory PNGs come from one encoder (encode below): write_png writes its bytes with
// write_file_beside_and_rename (io.h).
#include <png.h>
#include <tripsitter/display/png.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <span>
#include <vector>

namespace tripsitter::display {
namespace {

// Largest image read_png accepts, in pixels (a guard against absurd headers, far above any frame we make).
constexpr std::size_t kMaxReadPixels = std::size_t{1} << 28;

IoError error(const std::string& what, const std::string& path, const std::string& reason) {
  return IoError{what + " '" + path + "': " + reason};
}

// The one PNG encoder of write_png and encode_png: 8-bit RGB into `out`. Returns why it failed, or "" on success.
std::string encode(const core::ImageRgb8& image, std::vector<std::uint8_t>& out) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != 3 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height)) {
    return "image is empty or its pixel count does not match its size";
  }
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  // libpng's bound on the file's size: one pass of compression into a buffer that surely holds it.
  png_alloc_size_t size = PNG_IMAGE_PNG_SIZE_MAX(png);
  out.assign(static_cast<std::size_t>(size), 0);
  const bool written = png_image_write_to_memory(&png, out.data(), &size, 0, image.pixels.data(), 0, nullptr) != 0;
  const std::string png_message = png.message;
  png_image_free(&png);
  if (!written) {
    out.clear();
    return "libpng: " + png_message;
  }
  out.resize(static_cast<std::size_t>(size));
  return "";
}

}  // namespace

core::Result<std::vector<std::uint8_t>, IoError> encode_png(const core::ImageRgb8& image) {
  std::vector<std::uint8_t> bytes;
  const std::string reason = encode(image, bytes);
  if (!reason.empty()) return IoError{"cannot encode PNG: " + reason};
  return bytes;
}

core::Result<bool, IoError> write_png(const std::string& path, const core::ImageRgb8& image) {
  const char* kWhat = "cannot write PNG";
  std::vector<std::uint8_t> bytes;
  if (std::string reason = encode(image, bytes); !reason.empty()) return error(kWhat, path, reason);
  return write_file_beside_and_rename(
      path, std::span<const char>(reinterpret_cast<const char*>(bytes.data()), bytes.size()), kWhat);
}

core::Result<bool, IoError> write_png(const std::string& path, const core::Image444& image) {
  if (image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height))
    return error("cannot write PNG", path, "image is empty or its pixel count does not match its size");
  return write_png(path, core::to_rgb8(image));
}

core::Result<core::Image444, IoError> read_png(const std::string& path) {
  const char* kWhat = "cannot read PNG";
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&png, path.c_str()) == 0) {
    // On failure libpng has already released what it allocated.
    return error(kWhat, path, std::string("libpng: ") + png.message);
  }
  const std::size_t pixels = static_cast<std::size_t>(png.width) * static_cast<std::size_t>(png.height);
  if (pixels == 0 || pixels > kMaxReadPixels) {
    png_image_free(&png);
    return error(kWhat, path,
                 "image size " + std::to_string(png.width) + "x" + std::to_string(png.height) + " is out of range");
  }
  // Alpha, if any, is composited onto the buffer's initial black; opaque pixels keep their exact values.
  png.format = PNG_FORMAT_RGB;
  std::vector<std::uint8_t> rgb(pixels * 3, 0);
  if (png_image_finish_read(&png, nullptr, rgb.data(), 0, nullptr) == 0) {
    return error(kWhat, path, std::string("libpng: ") + png.message);  // finish_read frees on failure too
  }

  core::Image444 image(static_cast<int>(png.width), static_cast<int>(png.height));
  const auto to4 = [](std::uint8_t v) { return (v + 8) / 17; };  // nearest of 0, 17, ..., 255
  for (std::size_t i = 0; i < pixels; ++i) {
    image.pixels[i] = core::Rgb444::from_channels(to4(rgb[3 * i]), to4(rgb[3 * i + 1]), to4(rgb[3 * i + 2]));
  }
  return image;
}

}  // namespace tripsitter::display
