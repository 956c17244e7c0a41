#include <gtest/gtest.h>
#include <tripsitter/display/exr.h>
#include <tripsitter/display/png.h>
#include <tripsitter/display/test_util.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <Imath/half.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace tripsitter::display {
namespace {

namespace fs = std::filesystem;

// Each test gets a fresh, empty directory, removed afterwards.
class ExrTest : public testing::TempDirTest {};

std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }

std::vector<char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write_bytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// One of each class of float, then random bit patterns (any of which may be a NaN or a denormal), `count` in all.
std::vector<float> float_classes(std::size_t count, std::uint32_t seed) {
  using limits = std::numeric_limits<float>;
  std::vector<float> values = {
      0.0f, -0.0f, 1.0f, -1.0f, 0.1f, -3.14159265f,
      limits::min(), -limits::min(),                                  // smallest normal
      limits::denorm_min(), -limits::denorm_min(),                    // smallest denormal
      std::bit_cast<float>(0x00400001u), std::bit_cast<float>(0x807fffffu),  // other denormals
      limits::max(), limits::lowest(), limits::infinity(), -limits::infinity(),
      limits::quiet_NaN(), -limits::quiet_NaN(), std::bit_cast<float>(0x7fc12345u),  // NaNs with payloads
      65504.0f, 65519.0f, 65520.0f, -65520.0f, 1e6f,                   // half's largest, the overflow edge
      std::ldexp(1.0f, -14), std::ldexp(1.0f, -24), std::ldexp(1.0f, -25), std::ldexp(3.0f, -26),  // half's small
      1.0f + std::ldexp(1.0f, -11), 1.0f + std::ldexp(3.0f, -11),  // half's ties: to even, down then up
  };
  std::mt19937 rng(seed);
  while (values.size() < count) values.push_back(std::bit_cast<float>(static_cast<std::uint32_t>(rng())));
  values.resize(count);
  return values;
}

ExrImage one_channel_image(int w, int h, const std::vector<float>& values) {
  ExrImage image;
  image.width = w;
  image.height = h;
  image.channels.push_back(ExrChannel{"Y", values, std::nullopt});
  return image;
}

ExrImage written_and_read(const std::string& file, const ExrImage& image, ExrPixel pixel) {
  const auto written = write_exr(file, image, pixel);
  EXPECT_TRUE(written.ok()) << written.error().message;
  auto read = read_exr(file);
  EXPECT_TRUE(read.ok()) << read.error().message;
  return read.ok() ? std::move(read).value() : ExrImage{};
}

TEST_F(ExrTest, FloatRoundTripIsBitExactForEveryClassOfFloat) {
  const int w = 37, h = 23;
  const std::vector<float> values = float_classes(w * h, 1);
  const ExrImage read = written_and_read(path("f.exr"), one_channel_image(w, h, values), ExrPixel::kFloat);
  ASSERT_EQ(read.width, w);
  ASSERT_EQ(read.height, h);
  ASSERT_EQ(read.channels.size(), 1u);
  EXPECT_EQ(read.channels[0].name, "Y");
  EXPECT_EQ(read.channels[0].pixel, ExrPixel::kFloat);
  ASSERT_EQ(read.channels[0].values.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    EXPECT_EQ(bits(read.channels[0].values[i]), bits(values[i])) << "value " << i << ": " << values[i];
  }
  EXPECT_EQ(dir_entries(), std::vector<std::string>{"f.exr"}) << "temporary file left behind";
}

TEST_F(ExrTest, HalfRoundTripGivesTheValueRoundedToHalf) {
  const int w = 41, h = 19;
  const std::vector<float> values = float_classes(w * h, 2);
  const ExrImage read = written_and_read(path("h.exr"), one_channel_image(w, h, values), ExrPixel::kHalf);
  ASSERT_EQ(read.channels.size(), 1u);
  EXPECT_EQ(read.channels[0].pixel, ExrPixel::kHalf);
  ASSERT_EQ(read.channels[0].values.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float expected = static_cast<float>(Imath::half(values[i]));
    EXPECT_EQ(bits(read.channels[0].values[i]), bits(expected)) << "value " << i << ": " << values[i];
  }
}

TEST_F(ExrTest, HalfRoundingIsTheOneTheHeaderStates) {
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> values = {65504.0f, 65519.0f, 65520.0f, -1e6f, inf, -inf, std::ldexp(1.0f, -24),
                                     std::ldexp(1.0f, -25), 1.0f + std::ldexp(1.0f, -11), -0.0f,
                                     std::numeric_limits<float>::quiet_NaN()};
  const ExrImage read =
      written_and_read(path("h.exr"), one_channel_image(static_cast<int>(values.size()), 1, values), ExrPixel::kHalf);
  ASSERT_EQ(read.channels.size(), 1u);
  const std::vector<float>& v = read.channels[0].values;
  ASSERT_EQ(v.size(), values.size());
  EXPECT_EQ(v[0], 65504.0f);  // half's largest finite value
  EXPECT_EQ(v[1], 65504.0f);  // rounds down to it
  EXPECT_EQ(v[2], inf);  // rounds beyond it: infinity
  EXPECT_EQ(v[3], -inf);  // far beyond: infinity of its sign
  EXPECT_EQ(v[4], inf);  // infinities stay
  EXPECT_EQ(v[5], -inf);
  EXPECT_EQ(v[6], std::ldexp(1.0f, -24));  // half's smallest denormal stays
  EXPECT_EQ(bits(v[7]), bits(0.0f));  // half of it: a tie, to even (zero)
  EXPECT_EQ(v[8], 1.0f);  // a tie between 1 and its successor, to even
  EXPECT_EQ(bits(v[9]), bits(-0.0f));  // the sign of zero stays
  EXPECT_TRUE(std::isnan(v[10]));
}

TEST_F(ExrTest, LayersAndNamesRoundTripWithDepthAlwaysFloat) {
  const int w = 5, h = 4, n = w * h;
  std::vector<float> beauty(3 * n), albedo(3 * n), normal(3 * n), depth(n);
  for (int i = 0; i < 3 * n; ++i) {
    beauty[i] = 0.25f * static_cast<float>(i) + 1000.1f;  // not exact in half
    albedo[i] = 1.0f / static_cast<float>(i + 3);
    normal[i] = static_cast<float>(i % 3) - 1.0f;
  }
  for (int i = 0; i < n; ++i) depth[i] = 100.0f + 0.001f * static_cast<float>(i);  // steps far below half's 1/16
  depth[3] = std::numeric_limits<float>::infinity();  // the sky
  ExrImage image;
  image.width = w;
  image.height = h;
  add_rgb(image, "", beauty);
  add_rgb(image, "albedo", albedo);
  add_xyz(image, "normal", normal);
  add_depth(image, depth);

  for (const ExrPixel pixel : {ExrPixel::kHalf, ExrPixel::kFloat}) {
    SCOPED_TRACE(pixel == ExrPixel::kHalf ? "half" : "float");
    const ExrImage read = written_and_read(path("layers.exr"), image, pixel);
    std::vector<std::string> names;
    for (const ExrChannel& c : read.channels) names.push_back(c.name);
    // The file's order: sorted by name.
    EXPECT_EQ(names, (std::vector<std::string>{"B", "G", "R", "Z", "albedo.B", "albedo.G", "albedo.R", "normal.X",
                                               "normal.Y", "normal.Z"}));
    const auto stored = [&](float v) { return pixel == ExrPixel::kHalf ? static_cast<float>(Imath::half(v)) : v; };
    const std::pair<const char*, const std::vector<float>*> layers[] = {
        {"R", &beauty}, {"albedo.R", &albedo}, {"normal.X", &normal}};
    for (const auto& [first, interleaved] : layers) {
      for (int c = 0; c < 3; ++c) {
        std::string name = first;
        name.back() = std::string_view(first).ends_with('X') ? "XYZ"[c] : "RGB"[c];
        const ExrChannel* channel = find_channel(read, name);
        ASSERT_NE(channel, nullptr) << name;
        EXPECT_EQ(channel->pixel, pixel) << name;
        ASSERT_EQ(channel->values.size(), static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) EXPECT_EQ(channel->values[i], stored((*interleaved)[3 * i + c])) << name << i;
      }
    }
    const ExrChannel* z = find_channel(read, "Z");
    ASSERT_NE(z, nullptr);
    EXPECT_EQ(z->pixel, ExrPixel::kFloat);
    EXPECT_EQ(z->values, depth);
  }
}

TEST_F(ExrTest, AChannelsOwnTypeOverridesTheWritesType) {
  ExrImage image = one_channel_image(2, 1, {1000.1f, 0.3f});
  image.channels.push_back(ExrChannel{"alpha.A", {1000.1f, 0.3f}, ExrPixel::kHalf});
  const ExrImage read = written_and_read(path("mixed.exr"), image, ExrPixel::kFloat);
  const ExrChannel* y = find_channel(read, "Y");
  const ExrChannel* a = find_channel(read, "alpha.A");
  ASSERT_TRUE(y != nullptr && a != nullptr);
  EXPECT_EQ(y->pixel, ExrPixel::kFloat);
  EXPECT_EQ(y->values, image.channels[0].values);
  EXPECT_EQ(a->pixel, ExrPixel::kHalf);
  const auto as_half = [](float v) { return static_cast<float>(Imath::half(v)); };
  EXPECT_EQ(a->values, (std::vector<float>{as_half(1000.1f), as_half(0.3f)}));
}

TEST_F(ExrTest, OddSizesKeepTheirShapeAndRowOrder) {
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{7, 3}, std::pair{3, 7}, std::pair{1, 300}, std::pair{301, 2}}) {
    SCOPED_TRACE(::testing::Message() << w << "x" << h);
    std::vector<float> values(static_cast<std::size_t>(w * h));
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<float>(i);  // exact in half too
    for (const ExrPixel pixel : {ExrPixel::kHalf, ExrPixel::kFloat}) {
      const ExrImage read = written_and_read(path("odd.exr"), one_channel_image(w, h, values), pixel);
      EXPECT_EQ(read.width, w);
      EXPECT_EQ(read.height, h);
      ASSERT_EQ(read.channels.size(), 1u);
      EXPECT_EQ(read.channels[0].values, values);
    }
  }
  EXPECT_EQ(dir_entries(), std::vector<std::string>{"odd.exr"});
}

TEST_F(ExrTest, OverwritesAnExistingFile) {
  const std::string file = path("a.exr");
  write_bytes(file, std::vector<char>(100000, 'x'));
  const ExrImage read = written_and_read(file, one_channel_image(1, 1, {2.5f}), ExrPixel::kFloat);
  ASSERT_EQ(read.channels.size(), 1u);
  EXPECT_EQ(read.channels[0].values, std::vector<float>{2.5f});
  EXPECT_EQ(dir_entries(), std::vector<std::string>{"a.exr"});
}

TEST_F(ExrTest, AWriteToAMissingDirectoryFailsNamingThePathAndLeavesNothing) {
  const std::string file = path("missing/a.exr");
  const auto written = write_exr(file, one_channel_image(1, 1, {1.0f}), ExrPixel::kHalf);
  ASSERT_FALSE(written.ok());
  EXPECT_NE(written.error().message.find("cannot write EXR '" + file + "'"), std::string::npos)
      << written.error().message;
  EXPECT_TRUE(dir_entries().empty());
}

TEST_F(ExrTest, AWriteOntoADirectoryFailsAndLeavesNoTemporaryFile) {
  fs::create_directory(path("d.exr"));
  const auto written = write_exr(path("d.exr"), one_channel_image(1, 1, {1.0f}), ExrPixel::kFloat);
  ASSERT_FALSE(written.ok());
  EXPECT_NE(written.error().message.find(path("d.exr")), std::string::npos) << written.error().message;
  EXPECT_EQ(dir_entries(), std::vector<std::string>{"d.exr"});
  EXPECT_TRUE(fs::is_directory(path("d.exr")));
}

TEST_F(ExrTest, AnInvalidImageIsRefusedAndTheFileThereStaysAsItWas) {
  const std::string file = path("keep.exr");
  const std::vector<char> before = {'k', 'e', 'e', 'p'};
  write_bytes(file, before);
  ExrImage two = one_channel_image(2, 1, {1, 2});
  struct Case {
    const char* why;
    ExrImage image;
  };
  ExrImage repeated = two, unnamed = two, too_long = two, short_channel = two, no_channels = two;
  repeated.channels.push_back(repeated.channels[0]);
  unnamed.channels[0].name = "";
  too_long.channels[0].name = std::string(256, 'n');
  short_channel.channels[0].values.pop_back();
  no_channels.channels.clear();
  const Case cases[] = {{"repeated", repeated},   {"empty name", unnamed},
                        {"too long", too_long},   {"3 values", short_channel},
                        {"no channels", no_channels}, {"empty", one_channel_image(0, 0, {})},
                        {"negative", one_channel_image(-1, 1, {})}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.why);
    const auto written = write_exr(file, c.image, ExrPixel::kFloat);
    ASSERT_FALSE(written.ok());
    EXPECT_NE(written.error().message.find("cannot write EXR '" + file + "': "), std::string::npos)
        << written.error().message;
    EXPECT_EQ(file_bytes(file), before);
    EXPECT_EQ(dir_entries(), std::vector<std::string>{"keep.exr"});
  }
  // The longest name OpenEXR keeps is accepted.
  ExrImage longest = two;
  longest.channels[0].name = std::string(255, 'n');
  const ExrImage read = written_and_read(file, longest, ExrPixel::kHalf);
  ASSERT_EQ(read.channels.size(), 1u);
  EXPECT_EQ(read.channels[0].name, std::string(255, 'n'));
}

TEST_F(ExrTest, ReadingWhatIsNotAnExrFileFailsNamingThePath) {
  // A valid file, to cut short.
  const std::string good = path("good.exr");
  std::vector<float> values(64 * 64);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = std::sin(static_cast<float>(i));
  ASSERT_TRUE(write_exr(good, one_channel_image(64, 64, values), ExrPixel::kFloat).ok());
  const std::vector<char> exr = file_bytes(good);
  ASSERT_GT(exr.size(), 1000u);

  std::mt19937 rng(3);
  std::vector<char> garbage(5000);
  for (char& b : garbage) b = static_cast<char>(rng());
  const std::vector<char> png_magic = {'\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n', 0, 0, 0, 13};
  std::vector<char> magic_then_garbage = {'\x76', '\x2f', '\x31', '\x01', 2, 0, 0, 0};
  magic_then_garbage.insert(magic_then_garbage.end(), garbage.begin(), garbage.end());
  // The header's data window made 100000 x 100000 (xMax and yMax of the box2i attribute, little-endian).
  std::vector<char> huge_window = exr;
  const std::string key("dataWindow\0box2i\0", 17);
  const auto at = std::search(huge_window.begin(), huge_window.end(), key.begin(), key.end());
  ASSERT_NE(at, huge_window.end());
  const auto box = static_cast<std::size_t>(at - huge_window.begin()) + key.size() + 4;  // after the size
  for (const std::size_t field : {box + 8, box + 12}) {
    for (int i = 0; i < 4; ++i) huge_window[field + i] = static_cast<char>((99999 >> (8 * i)) & 0xFF);
  }
  const std::pair<const char*, std::vector<char>> files[] = {
      {"empty.exr", {}},
      {"garbage.exr", garbage},
      {"png.exr", png_magic},
      {"magic_then_garbage.exr", magic_then_garbage},
      {"header_only.exr", std::vector<char>(exr.begin(), exr.begin() + 200)},
      {"truncated.exr", std::vector<char>(exr.begin(), exr.begin() + static_cast<std::ptrdiff_t>(exr.size() / 2))},
      {"huge_window.exr", huge_window},
  };
  for (const auto& [name, bytes] : files) {
    SCOPED_TRACE(name);
    write_bytes(path(name), bytes);
    const auto read = read_exr(path(name));
    ASSERT_FALSE(read.ok());
    EXPECT_NE(read.error().message.find("cannot read EXR '" + path(name) + "': "), std::string::npos)
        << read.error().message;
  }
  const auto missing = read_exr(path("missing.exr"));
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("cannot read EXR '" + path("missing.exr") + "': "), std::string::npos)
      << missing.error().message;
  const auto directory = read_exr(dir_.string());
  EXPECT_FALSE(directory.ok());
}

TEST_F(ExrTest, ReadsTheDataWindowOfAFileWrittenByOpenExrItself) {
  // A data window away from the origin, inside a larger display window, with a half and a uint channel.
  const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(99, 99));
  const Imath::Box2i data(Imath::V2i(10, 20), Imath::V2i(12, 21));  // 3 x 2
  Imf::Header header(display, data);
  header.channels().insert("Y", Imf::Channel(Imf::HALF));
  header.channels().insert("id", Imf::Channel(Imf::UINT));
  std::vector<Imath::half> y = {1, 2, 3, 4, 5, 6};
  std::vector<std::uint32_t> id = {7, 8, 9, 10, 11, 12};
  Imf::FrameBuffer frame_buffer;
  frame_buffer.insert("Y", Imf::Slice::Make(Imf::HALF, y.data(), data, sizeof(Imath::half), 3 * sizeof(Imath::half)));
  frame_buffer.insert("id", Imf::Slice::Make(Imf::UINT, id.data(), data, 4, 12));
  {
    Imf::OutputFile file(path("window.exr").c_str(), header);
    file.setFrameBuffer(frame_buffer);
    file.writePixels(2);
  }
  const auto read = read_exr(path("window.exr"));
  ASSERT_TRUE(read.ok()) << read.error().message;
  EXPECT_EQ(read.value().width, 3);
  EXPECT_EQ(read.value().height, 2);
  const ExrChannel* read_y = find_channel(read.value(), "Y");
  const ExrChannel* read_id = find_channel(read.value(), "id");
  ASSERT_TRUE(read_y != nullptr && read_id != nullptr);
  EXPECT_EQ(read_y->values, (std::vector<float>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(read_y->pixel, ExrPixel::kHalf);
  EXPECT_EQ(read_id->values, (std::vector<float>{7, 8, 9, 10, 11, 12}));
  EXPECT_EQ(read_id->pixel, std::nullopt);
}

TEST(ExrChannels, AddRgbAndAddXyzSplitInterleavedTriples) {
  ExrImage image;
  const std::vector<float> triples = {1, 2, 3, 4, 5, 6};
  add_rgb(image, "", triples);
  add_rgb(image, "albedo", triples);
  add_xyz(image, "normal", triples);
  add_depth(image, std::vector<float>{9, 10});
  std::vector<std::string> names;
  for (const ExrChannel& c : image.channels) names.push_back(c.name);
  EXPECT_EQ(names, (std::vector<std::string>{"R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "normal.X",
                                             "normal.Y", "normal.Z", "Z"}));
  EXPECT_EQ(find_channel(image, "R")->values, (std::vector<float>{1, 4}));
  EXPECT_EQ(find_channel(image, "albedo.G")->values, (std::vector<float>{2, 5}));
  EXPECT_EQ(find_channel(image, "normal.Z")->values, (std::vector<float>{3, 6}));
  EXPECT_EQ(find_channel(image, "Z")->values, (std::vector<float>{9, 10}));
  EXPECT_EQ(find_channel(image, "Z")->pixel, ExrPixel::kFloat);
  EXPECT_EQ(find_channel(image, "R")->pixel, std::nullopt);
  EXPECT_EQ(find_channel(image, "nothing"), nullptr);
}

// io.h's write_image: a .exr name (any case) gets linear light and the feature buffers given as layers, any
// other name the sRGB picture as PNG.
TEST_F(ExrTest, AnImageFilesFormatIsChosenByItsName) {
  EXPECT_TRUE(is_exr("a/b.EXR"));
  EXPECT_FALSE(is_exr("b.exr.png"));
  core::ImageRgb8 rgb(2, 1);
  rgb.pixels = {255, 0, 0, 0, 0, 255};
  const core::ImageRgbF linear{2, 1, {{1, 0, 0}, {0, 0, 0.5f}}};
  const std::vector<core::Vec3f> albedo{{0.5f, 0.5f, 0.5f}, {1, 1, 1}}, normal{{0, 0, 1}, {0, 1, 0}};
  const std::vector<float> depth{2.0f, std::numeric_limits<float>::infinity()};
  ASSERT_TRUE(write_image(path("plain.exr"), {.rgb = rgb, .linear = linear}, ExrPixel::kFloat).ok());
  ASSERT_TRUE(write_image(path("layers.Exr"), {.rgb = rgb, .linear = linear, .albedo = albedo, .normal = normal,
                                               .depth = depth}, ExrPixel::kHalf).ok());
  ASSERT_TRUE(write_image(path("picture.png"), {.rgb = rgb, .linear = linear, .albedo = albedo}, ExrPixel::kHalf).ok());
  const auto plain = read_exr(path("plain.exr"));
  ASSERT_TRUE(plain.ok());
  ASSERT_EQ(plain.value().channels.size(), 3u);
  EXPECT_EQ(find_channel(plain.value(), "B")->values, (std::vector<float>{0, 0.5f}));
  const auto layers = read_exr(path("layers.Exr"));
  ASSERT_TRUE(layers.ok());
  EXPECT_EQ(layers.value().channels.size(), 10u);
  EXPECT_EQ(find_channel(layers.value(), "normal.Y")->values, (std::vector<float>{0, 1}));
  EXPECT_EQ(find_channel(layers.value(), "Z")->values, depth);
  EXPECT_EQ(find_channel(layers.value(), "Z")->pixel, ExrPixel::kFloat);
  const auto png = read_png(path("picture.png"));
  ASSERT_TRUE(png.ok());
  EXPECT_EQ(png.value().at(0, 0), core::Rgb444(0xf00));
  EXPECT_EQ(png.value().at(1, 0), core::Rgb444(0x00f));
}

}  // namespace
}  // namespace tripsitter::display
