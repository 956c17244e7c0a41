// PNG through libpng's simplified API (png_image), which reports errors in the struct instead of longjmp. Files and
// in-memory PNGs come from one encoder (encode below): write_png writes its bytes beside the file and renames.
#include <png.h>
#include <tripsitter/display/png.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <system_error>
#include <vector>

namespace tripsitter::display {
namespace {

// Largest image read_png accepts, in pixels (a guard against absurd headers, far above any frame we make).
constexpr std::size_t kMaxReadPixels = std::size_t{1} << 28;

IoError error(const std::string& what, const std::string& path, const std::string& reason) {
  return IoError{what + " '" + path + "': " + reason};
}

std::string errno_message(int e) { return std::generic_category().message(e); }

// Creates a new file "<path>.tmp-XXXXXXXX" that did not exist before ("x": exclusive). On failure returns
// nullptr with the errno of the last attempt in `err`.
std::FILE* create_temp_beside(const std::string& path, std::string& tmp_path, int& err) {
  std::random_device rd;
  std::mt19937 gen(rd());
  for (int attempt = 0; attempt < 16; ++attempt) {
    char suffix[16];
    std::snprintf(suffix, sizeof suffix, "%08x", static_cast<unsigned>(gen()));
    tmp_path = path + ".tmp-" + suffix;
    errno = 0;
    if (std::FILE* f = std::fopen(tmp_path.c_str(), "wbx")) return f;
    err = errno;
    if (err != EEXIST) return nullptr;
  }
  return nullptr;
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

  std::string tmp_path;
  int err = 0;
  std::FILE* f = create_temp_beside(path, tmp_path, err);
  if (f == nullptr) return error(kWhat, path, "cannot create temporary file '" + tmp_path + "': " + errno_message(err));

  errno = 0;
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int write_errno = errno;
  const bool flushed = std::fflush(f) == 0 && std::ferror(f) == 0;
  const int flush_errno = errno;
  const bool closed = std::fclose(f) == 0;
  const int close_errno = errno;

  std::string reason;
  if (!written) {
    reason = errno_message(write_errno);
  } else if (!flushed) {
    reason = errno_message(flush_errno);
  } else if (!closed) {
    reason = errno_message(close_errno);
  } else {
    std::error_code ec;
    std::filesystem::rename(tmp_path, path, ec);
    if (!ec) return true;
    reason = "cannot rename '" + tmp_path + "': " + ec.message();
  }
  std::error_code ignored;
  std::filesystem::remove(tmp_path, ignored);
  return error(kWhat, path, reason);
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
