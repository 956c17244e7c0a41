#include <tripsitter/link/wire_v1.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace tripsitter::link {
namespace {

V1Sphere random_v1_sphere(std::mt19937& rng) {
  auto pick = [&rng](std::int64_t lo, std::int64_t hi) {
    return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng);
  };
  V1Sphere s;
  s.x_raw = static_cast<std::int32_t>(pick(kV1X.min_raw(), kV1X.max_raw()));
  s.y_raw = static_cast<std::int32_t>(pick(kV1Y.min_raw(), kV1Y.max_raw()));
  s.z_raw = static_cast<std::int32_t>(pick(kV1Z.min_raw(), kV1Z.max_raw()));
  s.radius_log2 = static_cast<std::uint8_t>(pick(0, kV1RadiusLog2Max));
  s.colour = static_cast<std::uint16_t>(pick(0, 0xFFF));
  return s;
}

// SPEC.md section B: a sphere at x = 100, y = 50, z = 300 with r = 4 is the word 0x0320032025804000.
TEST(WireV1, SpecExampleWord) {
  V1Sphere s;
  s.x_raw = 100 * 8;  // 3 fractional bits
  s.y_raw = 50 * 8;
  s.z_raw = 300 * 8;
  s.radius_log2 = 4;
  s.colour = 0;
  ASSERT_EQ(s.x_raw, 800);
  ASSERT_EQ(s.y_raw, 400);
  ASSERT_EQ(s.z_raw, 2400);
  EXPECT_EQ(encode_v1_word(s), 0x0320032025804000u);
  EXPECT_EQ(decode_v1_word(0x0320032025804000u), s);

  std::vector<std::uint8_t> bytes;
  append_v1_bytes(0x0320032025804000u, bytes);
  EXPECT_EQ(bytes, (std::vector<std::uint8_t>{0x03, 0x20, 0x03, 0x20, 0x25, 0x80, 0x40, 0x00}));
}

// SPEC.md section B's second example: (0, 0, 400) with r = 6.
TEST(WireV1, SpecCentredSphereWord) {
  V1Sphere s;
  s.z_raw = 400 * 8;
  s.radius_log2 = 6;
  EXPECT_EQ(encode_v1_word(s), 0x0000000032006000u);
}

// Each field alone lands on exactly its bits of the table in SPEC.md section B.
TEST(WireV1, FieldsOccupyTheirBits) {
  V1Sphere s;
  s.x_raw = -1;
  EXPECT_EQ(encode_v1_word(s), 0xFFFF000000000000u);
  s = {};
  s.y_raw = -1;
  EXPECT_EQ(encode_v1_word(s), 0x0000FFFE00000000u);
  s = {};
  s.z_raw = -1;
  EXPECT_EQ(encode_v1_word(s), 0x00000001FFFC0000u);
  s = {};
  s.radius_log2 = 63;
  EXPECT_EQ(encode_v1_word(s), 0x000000000003F000u);
  s = {};
  s.colour = 0xFFF;
  EXPECT_EQ(encode_v1_word(s), 0x0000000000000FFFu);
}

TEST(WireV1, DecodeSignExtends) {
  const V1Sphere s = decode_v1_word(0xFFFFFFFFFFFFFFFFu);
  EXPECT_EQ(s.x_raw, -1);
  EXPECT_EQ(s.y_raw, -1);
  EXPECT_EQ(s.z_raw, -1);
  EXPECT_EQ(s.radius_log2, 63);
  EXPECT_EQ(s.colour, 0xFFF);
  // Only the top bit of each coordinate set: the most negative value.
  const V1Sphere m = decode_v1_word(0x8000800100000000u);
  EXPECT_EQ(m.x_raw, kV1X.min_raw());
  EXPECT_EQ(m.y_raw, kV1Y.min_raw());
  EXPECT_EQ(m.z_raw, kV1Z.min_raw());
}

TEST(WireV1, RoundTripOfRandomFields) {
  std::mt19937 rng(1);
  for (int i = 0; i < 10000; ++i) {
    const V1Sphere s = random_v1_sphere(rng);
    ASSERT_EQ(decode_v1_word(encode_v1_word(s)), s) << "iteration " << i;
  }
}

TEST(WireV1, RoundTripOfFieldExtremes) {
  const std::int64_t xs[] = {kV1X.min_raw(), -1, 0, 1, kV1X.max_raw()};
  const std::int64_t ys[] = {kV1Y.min_raw(), -1, 0, 1, kV1Y.max_raw()};
  const std::int64_t zs[] = {kV1Z.min_raw(), -1, 0, 1, kV1Z.max_raw()};
  const int rs[] = {0, 1, kV1RadiusLog2Max};
  const int colours[] = {0, 0x00F, 0x0F0, 0xF00, 0xFFF};
  int cases = 0;
  for (auto x : xs)
    for (auto y : ys)
      for (auto z : zs)
        for (int r : rs)
          for (int c : colours) {
            V1Sphere s;
            s.x_raw = static_cast<std::int32_t>(x);
            s.y_raw = static_cast<std::int32_t>(y);
            s.z_raw = static_cast<std::int32_t>(z);
            s.radius_log2 = static_cast<std::uint8_t>(r);
            s.colour = static_cast<std::uint16_t>(c);
            ASSERT_EQ(decode_v1_word(encode_v1_word(s)), s);
            ++cases;
          }
  EXPECT_EQ(cases, 5 * 5 * 5 * 3 * 5);
  EXPECT_EQ(kV1X.min_raw(), -32768);
  EXPECT_EQ(kV1X.max_raw(), 32767);
  EXPECT_EQ(kV1Y.min_raw(), -16384);
  EXPECT_EQ(kV1Z.max_raw(), 16383);
}

// The word has no invalid patterns: every 64-bit value decodes and encodes back to itself.
TEST(WireV1, EveryWordRoundTrips) {
  std::mt19937_64 rng(2);
  for (int i = 0; i < 10000; ++i) {
    const std::uint64_t word = rng();
    ASSERT_EQ(encode_v1_word(decode_v1_word(word)), word) << std::hex << word;
  }
}

TEST(WireV1, StreamReassemblesEveryTransferSize) {
  std::mt19937 rng(3);
  std::vector<V1Sphere> sent;
  std::vector<std::uint8_t> stream;
  for (int i = 0; i < 13; ++i) {
    sent.push_back(random_v1_sphere(rng));
    append_v1_bytes(encode_v1_word(sent.back()), stream);
  }
  ASSERT_EQ(stream.size(), sent.size() * kV1WordBytes);
  for (std::size_t transfer = 1; transfer <= 20; ++transfer) {
    std::vector<V1Sphere> received;
    V1StreamDecoder decoder([&received](const V1Sphere& s) { received.push_back(s); });
    for (std::size_t at = 0; at < stream.size(); at += transfer) {
      const std::size_t n = std::min(transfer, stream.size() - at);
      decoder.push(std::span<const std::uint8_t>(stream).subspan(at, n));
      EXPECT_EQ(decoder.pending_bytes(), (at + n) % kV1WordBytes);
    }
    EXPECT_EQ(received, sent) << "transfer size " << transfer;
    EXPECT_EQ(decoder.pending_bytes(), 0u);
  }
}

TEST(WireV1, ResetDropsPartialWord) {
  std::vector<V1Sphere> received;
  V1StreamDecoder decoder([&received](const V1Sphere& s) { received.push_back(s); });
  std::vector<std::uint8_t> bytes;
  append_v1_bytes(0x0320032025804000u, bytes);
  decoder.push(std::span<const std::uint8_t>(bytes).first(5));  // chip select goes high mid-word
  EXPECT_EQ(decoder.pending_bytes(), 5u);
  decoder.reset();
  EXPECT_EQ(decoder.pending_bytes(), 0u);
  decoder.push(bytes);
  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(encode_v1_word(received[0]), 0x0320032025804000u);
}

}  // namespace
}  // namespace tripsitter::link
