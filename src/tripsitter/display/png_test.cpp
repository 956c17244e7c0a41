#include <gtest/gtest.h>
#include <png.h>
#include <tripsitter/display/png.h>
#include <tripsitter/display/test_util.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace tripsitter::display {
namespace {

namespace fs = std::filesystem;

// Each test gets a fresh, empty directory, removed afterwards.
class PngTest : public testing::TempDirTest {};

core::Image444 random_image(int w, int h, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> colour(0, 0xFFF);
  core::Image444 image(w, h);
  for (auto& p : image.pixels) p = core::Rgb444(static_cast<std::uint16_t>(colour(rng)));
  return image;
}

// Writes raw 8-bit pixels with libpng directly, in the given png_image format.
void write_raw(const std::string& path, int w, int h, png_uint_32 format, const std::vector<std::uint8_t>& bytes) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(w);
  png.height = static_cast<png_uint_32>(h);
  png.format = format;
  ASSERT_NE(png_image_write_to_file(&png, path.c_str(), 0, bytes.data(), 0, nullptr), 0) << png.message;
}

TEST_F(PngTest, RoundTripOfARandom12BitImage) {
  for (const auto& [w, h] : {std::pair{640, 480}, std::pair{37, 23}, std::pair{1, 1}, std::pair{1, 300}}) {
    SCOPED_TRACE(::testing::Message() << w << "x" << h);
    const core::Image444 image = random_image(w, h, static_cast<std::uint32_t>(w * 1000 + h));
    const std::string file = path("frame.png");
    const auto written = write_png(file, image);
    ASSERT_TRUE(written.ok()) << written.error().message;
    const auto read = read_png(file);
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read.value(), image);
    EXPECT_EQ(dir_entries(), std::vector<std::string>{"frame.png"}) << "temporary file left behind";
  }
}

TEST_F(PngTest, WritesAn8BitRgbFileWithChannelsTimes17) {
  core::Image444 image(3, 1);
  image.at(0, 0) = core::Rgb444(0x000);
  image.at(1, 0) = core::Rgb444(0xF8F);
  image.at(2, 0) = core::Rgb444(0x036);
  const std::string file = path("a.png");
  ASSERT_TRUE(write_png(file, image).ok());

  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  ASSERT_NE(png_image_begin_read_from_file(&png, file.c_str()), 0) << png.message;
  EXPECT_EQ(png.width, 3u);
  EXPECT_EQ(png.height, 1u);
  EXPECT_EQ(png.format, static_cast<png_uint_32>(PNG_FORMAT_RGB)) << "8-bit RGB, no alpha, not colour-mapped";
  std::vector<std::uint8_t> bytes(PNG_IMAGE_SIZE(png));
  ASSERT_NE(png_image_finish_read(&png, nullptr, bytes.data(), 0, nullptr), 0) << png.message;
  EXPECT_EQ(bytes, (std::vector<std::uint8_t>{0, 0, 0, 255, 136, 255, 0, 51, 102}));
}

TEST_F(PngTest, ReadRoundsEach8BitValueToTheNearest4BitLevel) {
  std::vector<std::uint8_t> bytes;
  for (int v = 0; v < 256; ++v) {
    bytes.push_back(static_cast<std::uint8_t>(v));
    bytes.push_back(static_cast<std::uint8_t>(255 - v));
    bytes.push_back(static_cast<std::uint8_t>((v * 7) % 256));
  }
  const std::string file = path("levels.png");
  write_raw(file, 256, 1, PNG_FORMAT_RGB, bytes);
  const auto read = read_png(file);
  ASSERT_TRUE(read.ok()) << read.error().message;
  ASSERT_EQ(read.value().width, 256);
  ASSERT_EQ(read.value().height, 1);
  const auto nearest = [](int v) { return static_cast<int>(std::lround(v / 17.0)); };
  for (int v = 0; v < 256; ++v) {
    const core::Rgb444 c = read.value().at(v, 0);
    EXPECT_EQ(c.r(), nearest(v)) << v;
    EXPECT_EQ(c.g(), nearest(255 - v)) << v;
    EXPECT_EQ(c.b(), nearest((v * 7) % 256)) << v;
  }
}

TEST_F(PngTest, ReadsOpaqueRgba) {
  const core::Image444 image = random_image(20, 10, 5);
  std::vector<std::uint8_t> bytes;
  for (const core::Rgb444 p : image.pixels) {
    for (const int c : {p.r(), p.g(), p.b()}) bytes.push_back(core::Rgb444::expand(c));
    bytes.push_back(255);
  }
  const std::string file = path("rgba.png");
  write_raw(file, 20, 10, PNG_FORMAT_RGBA, bytes);
  const auto read = read_png(file);
  ASSERT_TRUE(read.ok()) << read.error().message;
  EXPECT_EQ(read.value(), image);
}

TEST_F(PngTest, OverwritesAnExistingFile) {
  const std::string file = path("frame.png");
  ASSERT_TRUE(write_png(file, random_image(8, 8, 1)).ok());
  const core::Image444 second = random_image(5, 9, 2);
  ASSERT_TRUE(write_png(file, second).ok());
  const auto read = read_png(file);
  ASSERT_TRUE(read.ok()) << read.error().message;
  EXPECT_EQ(read.value(), second);
  EXPECT_EQ(dir_entries(), std::vector<std::string>{"frame.png"});
}

TEST_F(PngTest, WriteIntoAMissingDirectoryFailsAndCreatesNothing) {
  const std::string file = path("missing/frame.png");
  const auto written = write_png(file, random_image(4, 4, 3));
  ASSERT_FALSE(written.ok());
  EXPECT_NE(written.error().message.find(file), std::string::npos) << written.error().message;
  EXPECT_NE(written.error().message.find("No such file or directory"), std::string::npos) << written.error().message;
  EXPECT_FALSE(fs::exists(path("missing")));
  EXPECT_TRUE(dir_entries().empty());
}

TEST_F(PngTest, WriteOverADirectoryFailsAndLeavesNoTemporary) {
  // The temporary file can be made, but renaming it onto a directory fails: the temporary must go.
  const std::string file = path("taken");
  fs::create_directory(file);
  const auto written = write_png(file, random_image(4, 4, 3));
  ASSERT_FALSE(written.ok());
  EXPECT_NE(written.error().message.find(file), std::string::npos) << written.error().message;
  EXPECT_EQ(dir_entries(), std::vector<std::string>{"taken"});
  EXPECT_TRUE(fs::is_directory(file));
}

TEST_F(PngTest, WriteRejectsMalformedImages) {
  core::Image444 empty;
  core::Image444 inconsistent(4, 4);
  inconsistent.pixels.pop_back();
  for (const core::Image444* image : {&empty, &inconsistent}) {
    const auto written = write_png(path("bad.png"), *image);
    ASSERT_FALSE(written.ok());
    EXPECT_NE(written.error().message.find(path("bad.png")), std::string::npos);
  }
  EXPECT_TRUE(dir_entries().empty());
}

TEST_F(PngTest, ReadErrorsNameThePath) {
  const std::string missing = path("nope.png");
  const auto r1 = read_png(missing);
  ASSERT_FALSE(r1.ok());
  EXPECT_NE(r1.error().message.find(missing), std::string::npos) << r1.error().message;

  const std::string garbage = path("garbage.png");
  std::ofstream(garbage) << "this is not a PNG file";
  const auto r2 = read_png(garbage);
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.error().message.find(garbage), std::string::npos) << r2.error().message;

  // A valid file cut short: the header reads, the pixels do not.
  const std::string whole = path("whole.png");
  ASSERT_TRUE(write_png(whole, random_image(64, 64, 4)).ok());
  const auto size = fs::file_size(whole);
  const std::string cut = path("cut.png");
  fs::copy_file(whole, cut);
  fs::resize_file(cut, size / 2);
  const auto r3 = read_png(cut);
  ASSERT_FALSE(r3.ok());
  EXPECT_NE(r3.error().message.find(cut), std::string::npos) << r3.error().message;
}

// encode_png's bytes decode (libpng, from memory) to the same 8-bit pixels, and are the bytes write_png writes.
TEST_F(PngTest, EncodeRoundTripsAn8BitImageAndMatchesTheFile) {
  for (const auto& [w, h] : {std::pair{160, 120}, std::pair{37, 23}, std::pair{1, 1}}) {
    SCOPED_TRACE(::testing::Message() << w << "x" << h);
    std::mt19937 rng(static_cast<std::uint32_t>(w * 7 + h));
    std::uniform_int_distribution<int> byte(0, 255);
    core::ImageRgb8 image(w, h);
    for (auto& v : image.pixels) v = static_cast<std::uint8_t>(byte(rng));

    const auto encoded = encode_png(image);
    ASSERT_TRUE(encoded.ok()) << encoded.error().message;
    const std::vector<std::uint8_t>& bytes = encoded.value();
    ASSERT_GT(bytes.size(), 8u);
    EXPECT_EQ(std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + 8),
              (std::vector<std::uint8_t>{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}));

    png_image png;
    std::memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    ASSERT_NE(png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()), 0) << png.message;
    EXPECT_EQ(png.width, static_cast<png_uint_32>(w));
    EXPECT_EQ(png.height, static_cast<png_uint_32>(h));
    png.format = PNG_FORMAT_RGB;
    std::vector<std::uint8_t> decoded(PNG_IMAGE_SIZE(png));
    ASSERT_NE(png_image_finish_read(&png, nullptr, decoded.data(), 0, nullptr), 0) << png.message;
    EXPECT_EQ(decoded, image.pixels);

    const std::string file = path("same.png");
    ASSERT_TRUE(write_png(file, image).ok());
    std::ifstream in(file, std::ios::binary);
    const std::vector<std::uint8_t> on_disk((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(on_disk, bytes) << "write_png and encode_png share one encoder";
  }
}

TEST_F(PngTest, EncodeRejectsMalformedImages) {
  core::ImageRgb8 empty;
  core::ImageRgb8 inconsistent(4, 4);
  inconsistent.pixels.pop_back();
  for (const core::ImageRgb8* image : {&empty, &inconsistent}) {
    const auto encoded = encode_png(*image);
    ASSERT_FALSE(encoded.ok());
    EXPECT_NE(encoded.error().message.find("cannot encode PNG"), std::string::npos) << encoded.error().message;
  }
}

}  // namespace
}  // namespace tripsitter::display
