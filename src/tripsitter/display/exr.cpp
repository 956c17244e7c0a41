// EXR through OpenEXR's C++ API (Imf). The file is made in memory (MemoryStream below) and written with
// write_file_beside_and_rename (io.h), so only whole files ever appear under their names. OpenEXR reports
// errors by throwing Iex exceptions (all std::exceptions): each call into it is wrapped, and its message becomes
// the IoError's reason. OutputFile takes each channel in its file's type (it converts only when reading), so half
// values are rounded here, with Imath::half: the rounding exr.h states.
#include <tripsitter/display/exr.h>

#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfPixelType.h>
#include <Imath/half.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <set>
#include <utility>

namespace tripsitter::display {
namespace {

// Most values (pixels times channels) read_exr accepts: 1 GiB of floats, a guard against absurd headers.
constexpr std::int64_t kMaxReadValues = std::int64_t{1} << 28;
// OpenEXR's longest channel name (Imf::Name silently cuts longer ones).
constexpr std::size_t kMaxNameBytes = 255;

IoError error(const std::string& what, const std::string& path, const std::string& reason) {
  return IoError{what + " '" + path + "': " + reason};
}

std::string openexr_reason(const std::exception& e) {
  std::string reason = "OpenEXR: ";
  reason += e.what();
  return reason;
}

// An Imf::OStream into a growing byte buffer. OpenEXR seeks back to fill in the table of scanline offsets.
class MemoryStream final : public Imf::OStream {
 public:
  explicit MemoryStream(const std::string& name) : Imf::OStream(name.c_str()) {}

  void write(const char c[], int n) override {
    const std::size_t count = static_cast<std::size_t>(std::max(n, 0));
    if (bytes_.size() < position_ + count) bytes_.resize(position_ + count, 0);
    if (count != 0) std::memcpy(bytes_.data() + position_, c, count);
    position_ += count;
  }
  std::uint64_t tellp() override { return position_; }
  void seekp(std::uint64_t position) override { position_ = static_cast<std::size_t>(position); }

  const std::vector<char>& bytes() const { return bytes_; }

 private:
  std::vector<char> bytes_;
  std::size_t position_ = 0;
};

// Why write_exr must refuse the image, or "".
std::string invalid(const ExrImage& image) {
  if (image.width <= 0 || image.height <= 0) return "image is empty";
  if (image.channels.empty()) return "image has no channels";
  const std::size_t pixels = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  std::set<std::string_view> names;
  for (const ExrChannel& channel : image.channels) {
    if (channel.name.empty()) return "a channel has an empty name";
    if (channel.name.size() > kMaxNameBytes) return "channel name '" + channel.name + "' is longer than 255 bytes";
    if (!names.insert(channel.name).second) return "channel name '" + channel.name + "' is repeated";
    if (channel.values.size() != pixels) {
      std::string reason = "channel '" + channel.name + "' has ";
      reason += std::to_string(channel.values.size());
      reason += " values, not width * height = ";
      reason += std::to_string(pixels);
      return reason;
    }
  }
  return "";
}

void add_interleaved(ExrImage& image, std::string_view layer, const char* const (&suffixes)[3],
                     std::span<const float> interleaved) {
  const std::size_t count = interleaved.size() / 3;
  for (std::size_t c = 0; c < 3; ++c) {
    ExrChannel channel;
    if (!layer.empty()) {
      channel.name = layer;
      channel.name += '.';
    }
    channel.name += suffixes[c];
    channel.values.resize(count);
    for (std::size_t i = 0; i < count; ++i) channel.values[i] = interleaved[3 * i + c];
    image.channels.push_back(std::move(channel));
  }
}

}  // namespace

void add_rgb(ExrImage& image, std::string_view layer, std::span<const float> rgb) {
  add_interleaved(image, layer, {"R", "G", "B"}, rgb);
}

void add_xyz(ExrImage& image, std::string_view layer, std::span<const float> xyz) {
  add_interleaved(image, layer, {"X", "Y", "Z"}, xyz);
}

void add_rgb(ExrImage& image, std::string_view layer, std::span<const core::Vec3f> rgb) {
  add_rgb(image, layer, std::span<const float>(&rgb.data()->x, 3 * rgb.size()));
}

void add_xyz(ExrImage& image, std::string_view layer, std::span<const core::Vec3f> xyz) {
  add_xyz(image, layer, std::span<const float>(&xyz.data()->x, 3 * xyz.size()));
}

void add_depth(ExrImage& image, std::span<const float> depth) {
  image.channels.push_back(ExrChannel{"Z", std::vector<float>(depth.begin(), depth.end()), ExrPixel::kFloat});
}

const ExrChannel* find_channel(const ExrImage& image, std::string_view name) {
  for (const ExrChannel& channel : image.channels) {
    if (channel.name == name) return &channel;
  }
  return nullptr;
}

core::Result<bool, IoError> write_exr(const std::string& path, const ExrImage& image, ExrPixel pixel) {
  const char* kWhat = "cannot write EXR";
  if (std::string reason = invalid(image); !reason.empty()) return error(kWhat, path, reason);

  const std::size_t pixels = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  // The half channels' values, rounded; the float channels are given to OpenEXR as they are.
  std::vector<std::vector<Imath::half>> halves;
  halves.reserve(image.channels.size());  // no reallocation: the slices point into the inner vectors
  MemoryStream stream(path);
  try {
    Imf::Header header(image.width, image.height);  // both windows (0,0)-(w-1,h-1), INCREASING_Y
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer frame_buffer;
    for (const ExrChannel& channel : image.channels) {
      const ExrPixel type = channel.pixel.value_or(pixel);
      char* base = nullptr;
      std::size_t size = 0;
      if (type == ExrPixel::kHalf) {
        std::vector<Imath::half>& rounded = halves.emplace_back(pixels);
        std::transform(channel.values.begin(), channel.values.end(), rounded.begin(),
                       [](float v) { return Imath::half(v); });
        base = reinterpret_cast<char*>(rounded.data());
        size = sizeof(Imath::half);
      } else {
        // OpenEXR only reads from a slice it is writing; its Slice holds a non-const pointer.
        base = reinterpret_cast<char*>(const_cast<float*>(channel.values.data()));
        size = sizeof(float);
      }
      const Imf::PixelType file_type = type == ExrPixel::kHalf ? Imf::HALF : Imf::FLOAT;
      header.channels().insert(channel.name, Imf::Channel(file_type));
      frame_buffer.insert(channel.name,
                          Imf::Slice(file_type, base, size, size * static_cast<std::size_t>(image.width)));
    }
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(frame_buffer);
    file.writePixels(image.height);
    // ~OutputFile writes the table of scanline offsets.
  } catch (const std::exception& e) {
    return error(kWhat, path, openexr_reason(e));
  }
  return write_file_beside_and_rename(path, stream.bytes(), kWhat);
}

core::Result<ExrImage, IoError> read_exr(const std::string& path) {
  const char* kWhat = "cannot read EXR";
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i window = header.dataWindow();
    const std::int64_t width = std::int64_t{window.max.x} - window.min.x + 1;
    const std::int64_t height = std::int64_t{window.max.y} - window.min.y + 1;
    std::int64_t channel_count = 0;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) ++channel_count;
    // Each factor is checked before the product, which then cannot overflow.
    if (width <= 0 || height <= 0 || width > kMaxReadValues || height > kMaxReadValues ||
        width * height > kMaxReadValues / std::max<std::int64_t>(channel_count, 1)) {
      std::string reason = "image size ";
      reason += std::to_string(width);
      reason += 'x';
      reason += std::to_string(height);
      reason += " with ";
      reason += std::to_string(channel_count);
      reason += " channels is out of range";
      return error(kWhat, path, reason);
    }
    if (!file.isComplete()) return error(kWhat, path, "file is incomplete (truncated or damaged)");

    ExrImage image;
    image.width = static_cast<int>(width);
    image.height = static_cast<int>(height);
    Imf::FrameBuffer frame_buffer;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      const Imf::Channel& channel = it.channel();
      if (channel.xSampling != 1 || channel.ySampling != 1) {
        return error(kWhat, path, std::string("channel '") + it.name() + "' is subsampled");
      }
      ExrChannel& out = image.channels.emplace_back();
      out.name = it.name();
      out.values.assign(static_cast<std::size_t>(width * height), 0.0f);
      if (channel.type == Imf::HALF) out.pixel = ExrPixel::kHalf;
      if (channel.type == Imf::FLOAT) out.pixel = ExrPixel::kFloat;
    }
    // Filled after the vector of channels stops growing, so the pointers stay valid.
    for (ExrChannel& out : image.channels) {
      frame_buffer.insert(out.name, Imf::Slice::Make(Imf::FLOAT, out.values.data(), window, sizeof(float),
                                                     sizeof(float) * static_cast<std::size_t>(width)));
    }
    file.setFrameBuffer(frame_buffer);
    file.readPixels(window.min.y, window.max.y);
    return image;
  } catch (const std::exception& e) {
    return error(kWhat, path, openexr_reason(e));
  }
}

}  // namespace tripsitter::display
