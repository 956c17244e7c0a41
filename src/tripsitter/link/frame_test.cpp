// Tests of the framed wires' codec and stream decoder on v2 (what v3 adds, its header check and sessions, is
// in wire_v3_test.cpp): round trips, reassembly, then one test per kind of damage, made by byte surgery on
// good frames (see docs/link_format.md for the layout).
#include <tripsitter/link/frame.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <tripsitter/core/crc32.h>

namespace tripsitter::link {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr std::uint32_t kLimit = 4096;  // the scene memory of the tests' receiver

// ---- worlds ----

WireSphere random_sphere(std::mt19937& rng) {
  auto pick = [&rng](std::int64_t lo, std::int64_t hi) {
    return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng);
  };
  WireSphere s;
  s.x = static_cast<std::int32_t>(pick(INT32_MIN, INT32_MAX));
  s.y = static_cast<std::int32_t>(pick(INT32_MIN, INT32_MAX));
  s.z = static_cast<std::int32_t>(pick(INT32_MIN, INT32_MAX));
  s.radius = static_cast<std::uint32_t>(pick(1, UINT32_MAX));
  s.material = static_cast<std::uint8_t>(pick(0, 2));
  for (auto& c : s.albedo) c = static_cast<std::uint8_t>(pick(0, 255));
  s.fuzz = static_cast<std::uint16_t>(pick(0, 65535));
  s.ior = static_cast<std::uint16_t>(pick(1, 65535));
  return s;
}

World random_world(std::mt19937& rng, std::size_t spheres) {
  World world;
  world.sequence = static_cast<std::uint32_t>(rng());
  world.frac_bits = static_cast<std::uint8_t>(rng() % (kMaxFracBits + 1));
  for (std::size_t i = 0; i < spheres; ++i) world.spheres.push_back(random_sphere(rng));
  return world;
}

// A small world whose bytes hold no 'T' outside the magic, so the hunt finds no false starts in it.
World plain_world(std::uint32_t sequence, std::size_t spheres) {
  World world;
  world.sequence = sequence;
  world.frac_bits = 4;
  for (std::size_t i = 0; i < spheres; ++i) {
    WireSphere s;
    s.x = static_cast<std::int32_t>(100 * i);
    s.z = 6400;
    s.radius = 1024;
    s.material = static_cast<std::uint8_t>(i % 3);
    s.albedo = {200, 100, 50};
    s.ior = 6144;
    world.spheres.push_back(s);
  }
  return world;
}

// ---- byte surgery ----

void set_u32(Bytes& bytes, std::size_t at, std::uint32_t value) {
  for (std::size_t k = 0; k < 4; ++k) bytes[at + k] = static_cast<std::uint8_t>(value >> (24 - 8 * k));
}

void flip_bit(Bytes& bytes, std::size_t bit) { bytes[bit / 8] ^= static_cast<std::uint8_t>(0x80u >> (bit % 8)); }

// Rewrites the trailer so that a deliberate edit is caught by the check under test, not by the CRC.
void fix_crc(Bytes& frame) {
  const std::size_t body = frame.size() - kFrameTrailerBytes;
  set_u32(frame, body, core::crc32(std::span<const std::uint8_t>(frame).first(body)));
}

Bytes concat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

std::size_t sphere_at(std::size_t index) { return kV2HeaderBytes + index * kSphereBytes; }

// ---- the receiver's side ----

struct Report {
  FrameError error;
  std::size_t offset;
  std::size_t dropped;
  std::string detail;
};

struct Recorder {
  std::vector<World> frames;
  std::vector<Report> errors;

  FrameStreamDecoder::Callbacks callbacks() {
    return {[this](World&& w) { frames.push_back(std::move(w)); },
            [this](const FrameFailure& f, std::size_t dropped) {
              errors.push_back({f.error, f.offset, dropped, f.detail});
            }};
  }
  std::size_t dropped() const {
    return std::accumulate(errors.begin(), errors.end(), std::size_t{0},
                           [](std::size_t sum, const Report& r) { return sum + r.dropped; });
  }
};

// Pushes `bytes` in transfers of `transfer` bytes (the last one shorter).
void feed(FrameStreamDecoder& decoder, const Bytes& bytes, std::size_t transfer) {
  for (std::size_t at = 0; at < bytes.size(); at += transfer) {
    decoder.push(std::span<const std::uint8_t>(bytes).subspan(at, std::min(transfer, bytes.size() - at)));
  }
}

// The whole life of a stream: all bytes in transfers of `transfer`, then the end of the stream.
Recorder receive(const Bytes& bytes, std::size_t transfer = 1, std::uint32_t limit = kLimit) {
  Recorder rec;
  FrameStreamDecoder decoder(WireVersion::kV2, limit, rec.callbacks());
  feed(decoder, bytes, transfer);
  decoder.end_of_stream();
  EXPECT_EQ(decoder.buffered_bytes(), 0u);
  EXPECT_EQ(rec.dropped() + [&rec] {
    std::size_t n = 0;
    for (const World& w : rec.frames) n += encode_frame(WireVersion::kV2, w).size();
    return n;
  }(), bytes.size()) << "every byte is delivered in a frame or counted as dropped exactly once";
  return rec;
}

FrameError decode_error(const Bytes& bytes, std::uint32_t limit = kLimit) {
  const auto result = decode_frame(WireVersion::kV2, bytes, limit);
  EXPECT_FALSE(result.ok());
  return result.ok() ? FrameError::kTrailingBytes : result.error().error;
}

std::size_t decode_error_offset(const Bytes& bytes, std::uint32_t limit = kLimit) {
  const auto result = decode_frame(WireVersion::kV2, bytes, limit);
  return result.ok() ? SIZE_MAX : result.error().offset;
}

// ---- round trips and layout ----

TEST(WireV2, RoundTripOfRandomWorlds) {
  std::mt19937 rng(20);
  for (std::size_t n : {0u, 1u, 2u, 7u, 100u, 4096u}) {
    for (int repeat = 0; repeat < 3; ++repeat) {
      const World world = random_world(rng, n);
      const Bytes frame = encode_frame(WireVersion::kV2, world);
      ASSERT_EQ(frame.size(), kV2HeaderBytes + n * kSphereBytes + kFrameTrailerBytes);
      const auto decoded = decode_frame(WireVersion::kV2, frame, kLimit);
      ASSERT_TRUE(decoded.ok()) << decoded.error().detail;
      EXPECT_EQ(decoded.value(), world) << n << " spheres";
    }
  }
}

// The worked example of docs/link_format.md, byte for byte.
TEST(WireV2, WorkedExampleOfTheDocument) {
  World world;
  world.sequence = 1;
  world.frac_bits = 4;
  WireSphere s;
  s.z = 6400;       // 400 pixel units with 4 fractional bits
  s.radius = 1024;  // 64 pixel units
  s.material = kMaterialLambertian;
  s.albedo = {204, 77, 77};
  s.fuzz = 0;
  s.ior = 6144;  // 1.5 in u4.12
  world.spheres.push_back(s);
  const Bytes expected = {
      0x54, 0x53, 0x57, 0x32, 0x02, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01,  // header
      0x00, 0x00, 0x00, 0x18,                                                                          //
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x19, 0x00, 0x00, 0x00, 0x04, 0x00,  // sphere
      0x00, 0xCC, 0x4D, 0x4D, 0x00, 0x00, 0x18, 0x00,                                                  //
      0xBC, 0x4B, 0xFA, 0x32,                                                                          // CRC
  };
  EXPECT_EQ(encode_frame(WireVersion::kV2, world), expected);
  const auto decoded = decode_frame(WireVersion::kV2, expected, kLimit);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded.value(), world);
}

TEST(WireV2, CrcCoversHeaderAndPayload) {
  std::mt19937 rng(21);
  const Bytes frame = encode_frame(WireVersion::kV2, random_world(rng, 3));
  const std::size_t body = frame.size() - kFrameTrailerBytes;
  const std::uint32_t crc = core::crc32(std::span<const std::uint8_t>(frame).first(body));
  EXPECT_EQ(frame[body], crc >> 24);
  EXPECT_EQ(frame[body + 3], crc & 0xFF);
}

TEST(WireV2, ErrorNames) {
  EXPECT_STREQ(to_string(FrameError::kBadMagic), "bad magic");
  EXPECT_STREQ(to_string(FrameError::kBadVersion), "bad version");
  EXPECT_STREQ(to_string(FrameError::kBadHeader), "bad header");
  EXPECT_STREQ(to_string(FrameError::kTooManySpheres), "too many spheres");
  EXPECT_STREQ(to_string(FrameError::kBadLength), "bad length");
  EXPECT_STREQ(to_string(FrameError::kTruncated), "truncated");
  EXPECT_STREQ(to_string(FrameError::kBadCrc), "bad CRC");
  EXPECT_STREQ(to_string(FrameError::kBadSphere), "bad sphere");
  EXPECT_STREQ(to_string(FrameError::kTrailingBytes), "trailing bytes");
}

// ---- reassembly ----

TEST(WireV2, StreamReassemblesEveryTransferSize) {
  std::mt19937 rng(22);
  const std::vector<World> worlds = {random_world(rng, 3), random_world(rng, 0), random_world(rng, 3)};
  Bytes stream;
  for (const World& w : worlds) stream = concat({stream, encode_frame(WireVersion::kV2, w)});
  const std::size_t frame_size = encode_frame(WireVersion::kV2, worlds[0]).size();
  for (std::size_t transfer = 1; transfer <= frame_size; ++transfer) {
    const Recorder rec = receive(stream, transfer);
    EXPECT_EQ(rec.frames, worlds) << "transfer size " << transfer;
    EXPECT_TRUE(rec.errors.empty()) << "transfer size " << transfer;
  }
}

TEST(WireV2, StreamTakesALargeFrameOneByteAtATime) {
  std::mt19937 rng(23);
  const World world = random_world(rng, kLimit);
  const Bytes frame = encode_frame(WireVersion::kV2, world);
  Recorder rec;
  FrameStreamDecoder decoder(WireVersion::kV2, kLimit, rec.callbacks());
  for (std::size_t i = 0; i + 1 < frame.size(); ++i) decoder.push(std::span<const std::uint8_t>(frame).subspan(i, 1));
  EXPECT_TRUE(rec.frames.empty());
  EXPECT_EQ(decoder.buffered_bytes(), frame.size() - 1);
  decoder.push(std::span<const std::uint8_t>(frame).last(1));
  ASSERT_EQ(rec.frames.size(), 1u);
  EXPECT_EQ(rec.frames[0], world);
  EXPECT_EQ(decoder.buffered_bytes(), 0u);
}

// ---- one test per kind of damage ----

TEST(WireV2, BadMagic) {
  const Bytes good = encode_frame(WireVersion::kV2, plain_world(1, 2));
  for (std::size_t at = 0; at < 4; ++at) {
    Bytes bad = good;
    bad[at] = 'X';
    EXPECT_EQ(decode_error(bad), FrameError::kBadMagic);
    EXPECT_EQ(decode_error_offset(bad), at);
    // The stream skips the whole bad frame as one run of garbage and takes the next.
    const Recorder rec = receive(concat({bad, good}));
    ASSERT_EQ(rec.frames.size(), 1u);
    ASSERT_EQ(rec.errors.size(), 1u);
    EXPECT_EQ(rec.errors[0].error, FrameError::kBadMagic);
    EXPECT_EQ(rec.errors[0].offset, 0u);
    EXPECT_EQ(rec.errors[0].dropped, bad.size());
  }
}

TEST(WireV2, BadVersion) {
  Bytes bad = encode_frame(WireVersion::kV2, plain_world(1, 2));
  bad[4] = 1;
  EXPECT_EQ(decode_error(bad), FrameError::kBadVersion);
  EXPECT_EQ(decode_error_offset(bad), 4u);
  const Bytes good = encode_frame(WireVersion::kV2, plain_world(2, 1));
  const Recorder rec = receive(concat({bad, good}));
  ASSERT_EQ(rec.frames.size(), 1u);
  EXPECT_EQ(rec.frames[0].sequence, 2u);
  ASSERT_EQ(rec.errors.size(), 2u);
  EXPECT_EQ(rec.errors[0].error, FrameError::kBadVersion);
  EXPECT_EQ(rec.errors[0].dropped, 1u);  // the frame's first byte; the rest is skipped by the hunt
  EXPECT_EQ(rec.errors[1].error, FrameError::kBadMagic);
  EXPECT_EQ(rec.errors[1].offset, 1u);
  EXPECT_EQ(rec.errors[1].dropped, bad.size() - 1);
}

TEST(WireV2, NonzeroReserved) {
  for (std::size_t at : {6u, 7u}) {
    Bytes bad = encode_frame(WireVersion::kV2, plain_world(1, 1));
    bad[at] = 0x01;
    EXPECT_EQ(decode_error(bad), FrameError::kBadHeader);
    EXPECT_EQ(decode_error_offset(bad), at);
    const Recorder rec = receive(bad);
    ASSERT_FALSE(rec.errors.empty());
    EXPECT_EQ(rec.errors[0].error, FrameError::kBadHeader);
    EXPECT_TRUE(rec.frames.empty());
  }
}

TEST(WireV2, FracBitsAboveThirty) {
  World world = plain_world(1, 1);
  world.frac_bits = kMaxFracBits;
  EXPECT_TRUE(decode_frame(WireVersion::kV2, encode_frame(WireVersion::kV2, world), kLimit).ok());
  Bytes bad = encode_frame(WireVersion::kV2, world);
  bad[5] = kMaxFracBits + 1;
  fix_crc(bad);
  EXPECT_EQ(decode_error(bad), FrameError::kBadHeader);
  EXPECT_EQ(decode_error_offset(bad), 5u);
}

TEST(WireV2, CountOverTheLimitIsRejectedFromTheHeaderAlone) {
  Bytes header = encode_frame(WireVersion::kV2, plain_world(1, 0));
  header.resize(kV2HeaderBytes);
  set_u32(header, 12, 0xFFFFFFFF);
  set_u32(header, 16, 0xFFFFFFFF);
  // Only the 20 header bytes exist: the decision cannot have needed the payload.
  EXPECT_EQ(decode_error(header), FrameError::kTooManySpheres);
  EXPECT_EQ(decode_error_offset(header), 12u);

  Recorder rec;
  FrameStreamDecoder decoder(WireVersion::kV2, kLimit, rec.callbacks());
  decoder.push(header);
  ASSERT_FALSE(rec.errors.empty());
  EXPECT_EQ(rec.errors[0].error, FrameError::kTooManySpheres);
  EXPECT_LT(decoder.buffered_bytes(), kV2HeaderBytes);  // nothing of the claimed 100 GB is held

  set_u32(header, 12, 5000000);
  const auto result = decode_frame(WireVersion::kV2, header, kLimit);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().detail, "sphere count 5000000 exceeds the scene memory of 4096 spheres");
}

TEST(WireV2, CountAtTheLimitPassesAndOneMoreDoesNot) {
  const Bytes three = encode_frame(WireVersion::kV2, plain_world(1, 3));
  EXPECT_TRUE(decode_frame(WireVersion::kV2, three, 3).ok());
  EXPECT_EQ(decode_error(three, 2), FrameError::kTooManySpheres);
  const Recorder rec = receive(three, 5, 2);
  EXPECT_TRUE(rec.frames.empty());
  ASSERT_FALSE(rec.errors.empty());
  EXPECT_EQ(rec.errors[0].error, FrameError::kTooManySpheres);
}

TEST(WireV2, LengthMismatch) {
  for (std::uint32_t length : {0u, 47u, 49u, 72u, 0xFFFFFFFFu}) {
    Bytes bad = encode_frame(WireVersion::kV2, plain_world(1, 2));
    set_u32(bad, 16, length);
    EXPECT_EQ(decode_error(bad), FrameError::kBadLength) << length;
    EXPECT_EQ(decode_error_offset(bad), 16u);
  }
}

TEST(WireV2, TruncatedFrame) {
  const Bytes good = encode_frame(WireVersion::kV2, plain_world(1, 2));
  for (std::size_t n = 0; n < good.size(); ++n) {
    const Bytes cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n));
    EXPECT_EQ(decode_error(cut), FrameError::kTruncated) << n << " bytes";
    EXPECT_EQ(decode_error_offset(cut), n);
    const Recorder rec = receive(cut, 3);
    EXPECT_TRUE(rec.frames.empty());
    if (n == 0) {
      EXPECT_TRUE(rec.errors.empty()) << "nothing buffered, nothing reported";
    } else {
      ASSERT_EQ(rec.errors.size(), 1u) << n << " bytes";
      EXPECT_EQ(rec.errors[0].error, FrameError::kTruncated);
      EXPECT_EQ(rec.errors[0].dropped, n);
    }
  }
}

TEST(WireV2, BitFlipInPayloadIsBadCrc) {
  const Bytes good = encode_frame(WireVersion::kV2, plain_world(1, 1));
  const std::size_t crc_at = good.size() - kFrameTrailerBytes;
  // Every bit of the payload, and of the sequence number, which has no check of its own.
  std::vector<std::size_t> bits;
  for (std::size_t bit = kV2HeaderBytes * 8; bit < crc_at * 8; ++bit) bits.push_back(bit);
  for (std::size_t bit = 8 * 8; bit < 12 * 8; ++bit) bits.push_back(bit);
  for (std::size_t bit : bits) {
    Bytes bad = good;
    flip_bit(bad, bit);
    ASSERT_EQ(decode_error(bad), FrameError::kBadCrc) << "bit " << bit;
    EXPECT_EQ(decode_error_offset(bad), crc_at);
  }
}

TEST(WireV2, BitFlipInCrc) {
  const Bytes good = encode_frame(WireVersion::kV2, plain_world(1, 1));
  for (std::size_t k = 0; k < 32; ++k) {
    Bytes bad = good;
    flip_bit(bad, (good.size() - kFrameTrailerBytes) * 8 + k);
    ASSERT_EQ(decode_error(bad), FrameError::kBadCrc) << "bit " << k;
  }
}

TEST(WireV2, BadSphere) {
  struct Case {
    const char* what;
    std::size_t field;  // offset in the sphere record
    std::uint8_t value;
    std::size_t width;
  };
  const Case cases[] = {{"radius 0", 12, 0, 4}, {"material 3", 16, 3, 1}, {"ior 0", 22, 0, 2}};
  const Bytes next = encode_frame(WireVersion::kV2, plain_world(9, 1));
  for (const Case& c : cases) {
    Bytes bad = encode_frame(WireVersion::kV2, plain_world(1, 3));
    const std::size_t at = sphere_at(2) + c.field;
    std::fill_n(bad.begin() + static_cast<std::ptrdiff_t>(at), c.width, std::uint8_t{0});
    bad[at + c.width - 1] = c.value;
    fix_crc(bad);
    EXPECT_EQ(decode_error(bad), FrameError::kBadSphere) << c.what;
    EXPECT_EQ(decode_error_offset(bad), at) << c.what;
    // The frame came through intact, so the stream drops exactly it and reads the next frame right after.
    const Recorder rec = receive(concat({bad, next}), 7);
    ASSERT_EQ(rec.errors.size(), 1u) << c.what;
    EXPECT_EQ(rec.errors[0].error, FrameError::kBadSphere);
    EXPECT_EQ(rec.errors[0].offset, at);
    EXPECT_EQ(rec.errors[0].dropped, bad.size());
    ASSERT_EQ(rec.frames.size(), 1u);
    EXPECT_EQ(rec.frames[0].sequence, 9u);
  }
}

TEST(WireV2, TrailingBytes) {
  const Bytes good = encode_frame(WireVersion::kV2, plain_world(1, 1));
  const Bytes longer = concat({good, Bytes{0x00}});
  EXPECT_EQ(decode_error(longer), FrameError::kTrailingBytes);
  EXPECT_EQ(decode_error_offset(longer), good.size());
  EXPECT_EQ(decode_error(concat({good, good})), FrameError::kTrailingBytes);
}

TEST(WireV2, GarbageBetweenTwoGoodFrames) {
  const Bytes first = encode_frame(WireVersion::kV2, plain_world(1, 2));
  const Bytes second = encode_frame(WireVersion::kV2, plain_world(2, 1));
  // Near misses of the magic, and a 'T' at the very end that only the next byte proves wrong.
  const Bytes garbage = {0x00, 'T', 'S', 'W', '3', 'T', 'T', 'S', 0xFF, 'S', 'W', '2', 0x54, 0x53, 0x57, 0x00, 'T'};
  const Bytes stream = concat({first, garbage, second});
  for (std::size_t transfer = 1; transfer <= stream.size(); ++transfer) {
    const Recorder rec = receive(stream, transfer);
    ASSERT_EQ(rec.frames.size(), 2u) << "transfer " << transfer;
    EXPECT_EQ(rec.frames[0].sequence, 1u);
    EXPECT_EQ(rec.frames[1].sequence, 2u);
    ASSERT_EQ(rec.errors.size(), 1u) << "transfer " << transfer;
    EXPECT_EQ(rec.errors[0].error, FrameError::kBadMagic);
    EXPECT_EQ(rec.errors[0].offset, first.size());
    EXPECT_EQ(rec.errors[0].dropped, garbage.size());
  }
}

TEST(WireV2, GarbageAtTheEndOfTheStream) {
  const Bytes good = encode_frame(WireVersion::kV2, plain_world(1, 1));
  const Bytes garbage = {0x01, 0x02, 'T', 'S', 'W'};  // ends in what could still become a magic
  const Recorder rec = receive(concat({good, garbage}), 2);
  ASSERT_EQ(rec.frames.size(), 1u);
  ASSERT_EQ(rec.errors.size(), 1u);
  EXPECT_EQ(rec.errors[0].error, FrameError::kBadMagic);
  EXPECT_EQ(rec.errors[0].dropped, garbage.size());
}

TEST(WireV2, GoodFrameAfterADamagedOneIsRecovered) {
  Bytes damaged = encode_frame(WireVersion::kV2, plain_world(1, 2));
  flip_bit(damaged, sphere_at(1) * 8 + 3);
  const Bytes good = encode_frame(WireVersion::kV2, plain_world(2, 2));
  for (std::size_t transfer : {1u, 5u, 64u, 1000u}) {
    const Recorder rec = receive(concat({damaged, good}), transfer);
    ASSERT_EQ(rec.frames.size(), 1u);
    EXPECT_EQ(rec.frames[0].sequence, 2u);
    ASSERT_EQ(rec.errors.size(), 2u);
    EXPECT_EQ(rec.errors[0].error, FrameError::kBadCrc);
    EXPECT_EQ(rec.errors[0].offset, damaged.size() - kFrameTrailerBytes);
    EXPECT_EQ(rec.errors[1].error, FrameError::kBadMagic);
    EXPECT_EQ(rec.errors[1].dropped, damaged.size() - 1);
  }
}

// The sender restarted mid-frame: the cut frame's declared length swallows the next frames, its CRC fails,
// and the hunt from its second byte finds the frames inside it.
TEST(WireV2, FramesInsideACutFrameAreRecovered) {
  const Bytes cut = [] {
    Bytes b = encode_frame(WireVersion::kV2, plain_world(1, 5));
    b.resize(40);
    return b;
  }();
  const Bytes b = encode_frame(WireVersion::kV2, plain_world(2, 1));
  const Bytes c = encode_frame(WireVersion::kV2, plain_world(3, 3));
  const Bytes stream = concat({cut, b, c});
  ASSERT_LT(stream.size() - c.size(), 20u + 5 * 24 + 4) << "the cut frame must reach into c";
  for (std::size_t transfer = 1; transfer <= stream.size(); ++transfer) {
    const Recorder rec = receive(stream, transfer);
    ASSERT_EQ(rec.frames.size(), 2u) << "transfer " << transfer;
    EXPECT_EQ(rec.frames[0].sequence, 2u);
    EXPECT_EQ(rec.frames[1].sequence, 3u);
    ASSERT_EQ(rec.errors.size(), 2u);
    EXPECT_EQ(rec.errors[0].error, FrameError::kBadCrc);
    EXPECT_EQ(rec.errors[0].dropped, 1u);
    EXPECT_EQ(rec.errors[1].error, FrameError::kBadMagic);
    EXPECT_EQ(rec.errors[1].dropped, cut.size() - 1);
  }
}

TEST(WireV2, EndOfStreamReportsAPartialFrame) {
  const Bytes good = encode_frame(WireVersion::kV2, plain_world(1, 2));
  Recorder rec;
  FrameStreamDecoder decoder(WireVersion::kV2, kLimit, rec.callbacks());
  decoder.push(good);
  decoder.push(std::span<const std::uint8_t>(good).first(30));
  EXPECT_EQ(decoder.buffered_bytes(), 30u);
  decoder.end_of_stream();
  ASSERT_EQ(rec.frames.size(), 1u);
  ASSERT_EQ(rec.errors.size(), 1u);
  EXPECT_EQ(rec.errors[0].error, FrameError::kTruncated);
  EXPECT_EQ(rec.errors[0].dropped, 30u);
  EXPECT_EQ(decoder.buffered_bytes(), 0u);
  // A new stream starts clean.
  decoder.push(good);
  EXPECT_EQ(rec.frames.size(), 2u);
  decoder.end_of_stream();
  EXPECT_EQ(rec.errors.size(), 1u);
}

// ---- properties ----

// One candidate frame, whole: the stream decoder and decode_frame agree on what is wrong with it.
TEST(WireV2, StreamAgreesWithDecodeFrame) {
  std::mt19937 rng(24);
  for (int i = 0; i < 3000; ++i) {
    Bytes frame = encode_frame(WireVersion::kV2, random_world(rng, rng() % 4));
    const int edits = static_cast<int>(rng() % 3);
    for (int e = 0; e < edits; ++e) frame[rng() % frame.size()] = static_cast<std::uint8_t>(rng() >> 5);
    if (rng() % 2) fix_crc(frame);
    const auto decoded = decode_frame(WireVersion::kV2, frame, 3);
    const Recorder rec = receive(frame, 1 + rng() % 40, 3);
    if (decoded.ok()) {
      ASSERT_EQ(rec.frames.size(), 1u);
      EXPECT_EQ(rec.frames[0], decoded.value());
      EXPECT_TRUE(rec.errors.empty());
    } else if (decoded.error().error != FrameError::kTrailingBytes && decoded.error().error != FrameError::kTruncated) {
      // (An edited count and length can make the frame shorter or longer than its bytes; the stream then
      // reads something else, so those cases say nothing here.)
      ASSERT_FALSE(rec.errors.empty());
      EXPECT_EQ(rec.errors[0].error, decoded.error().error) << decoded.error().detail;
      // A bad magic is reported at the wrong byte by decode_frame, at the start of the skipped run by
      // the stream.
      const std::size_t offset = decoded.error().error == FrameError::kBadMagic ? 0 : decoded.error().offset;
      EXPECT_EQ(rec.errors[0].offset, offset);
    }
  }
}

// Random streams built of good frames, damaged frames and garbage, cut into random transfers: the decoder
// never crashes, never holds more than one frame, delivers only frames that were in the input, and
// accounts for every byte (checked in receive()).
TEST(WireV2, FuzzNeverCrashesAndDeliversOnlyFramesFromTheInput) {
  std::mt19937 rng(25);
  constexpr std::uint32_t limit = 6;
  constexpr std::size_t max_frame = kV2HeaderBytes + limit * kSphereBytes + kFrameTrailerBytes;
  std::size_t delivered = 0;
  std::vector<bool> seen(static_cast<std::size_t>(FrameError::kTrailingBytes) + 1, false);
  for (int i = 0; i < 2000; ++i) {
    Bytes stream;
    const int pieces = static_cast<int>(rng() % 8);
    for (int p = 0; p < pieces; ++p) {
      Bytes piece;
      switch (rng() % 5) {
        case 0:  // pure garbage
          piece.resize(rng() % 64);
          for (auto& b : piece) b = static_cast<std::uint8_t>(rng());
          break;
        case 1:  // garbage full of magic fragments
          for (int k = static_cast<int>(rng() % 10); k > 0; --k) {
            piece.insert(piece.end(), kV2Magic.begin(), kV2Magic.begin() + 1 + rng() % 4);
            piece.push_back(static_cast<std::uint8_t>(rng()));
          }
          break;
        case 2: {  // a damaged frame, possibly with a valid CRC after the damage
          piece = encode_frame(WireVersion::kV2, random_world(rng, rng() % 8));
          for (int k = static_cast<int>(1 + rng() % 3); k > 0; --k) piece[rng() % piece.size()] ^= 1u << (rng() % 8);
          if (rng() % 2) fix_crc(piece);
          break;
        }
        case 3:  // a frame cut short
          piece = encode_frame(WireVersion::kV2, random_world(rng, rng() % 8));
          piece.resize(rng() % piece.size());
          break;
        default:  // a good frame
          piece = encode_frame(WireVersion::kV2, random_world(rng, rng() % (limit + 1)));
          break;
      }
      stream = concat({stream, piece});
    }
    Recorder rec;
    FrameStreamDecoder decoder(WireVersion::kV2, limit, rec.callbacks());
    for (std::size_t at = 0; at < stream.size();) {
      const std::size_t n = std::min<std::size_t>(1 + rng() % 50, stream.size() - at);
      decoder.push(std::span<const std::uint8_t>(stream).subspan(at, n));
      at += n;
      ASSERT_LT(decoder.buffered_bytes(), max_frame);
    }
    decoder.end_of_stream();
    std::size_t frame_bytes = 0;
    for (const World& w : rec.frames) {
      ASSERT_LE(w.spheres.size(), limit);
      const Bytes again = encode_frame(WireVersion::kV2, w);
      frame_bytes += again.size();
      ASSERT_NE(std::search(stream.begin(), stream.end(), again.begin(), again.end()), stream.end());
    }
    ASSERT_EQ(frame_bytes + rec.dropped(), stream.size());
    delivered += rec.frames.size();
    for (const Report& r : rec.errors) seen[static_cast<std::size_t>(r.error)] = true;
  }
  EXPECT_GT(delivered, 1000u) << "the fuzz should also carry many good frames";
  // Every error but kTrailingBytes, which is decode_frame's, and kBadHeaderCrc and kBadHierarchy, which v2 has
  // no header check and no hierarchy for.
  for (std::size_t e = 0; e + 1 < seen.size(); ++e) {
    if (static_cast<FrameError>(e) == FrameError::kBadHeaderCrc || static_cast<FrameError>(e) == FrameError::kBadHierarchy)
      continue;
    EXPECT_TRUE(seen[e]) << to_string(static_cast<FrameError>(e)) << " never happened";
  }
}

TEST(WireV2, PureRandomBytesNeverCrash) {
  std::mt19937 rng(26);
  for (int i = 0; i < 2000; ++i) {
    Bytes stream(rng() % 300);
    for (auto& b : stream) b = static_cast<std::uint8_t>(rng());
    // Plant a magic and a plausible version now and then so that the header checks get exercised too.
    if (stream.size() > 8 && rng() % 2) {
      const std::size_t at = rng() % (stream.size() - 8);
      std::copy(kV2Magic.begin(), kV2Magic.end(), stream.begin() + static_cast<std::ptrdiff_t>(at));
      stream[at + 4] = kV2Version;
    }
    const std::uint32_t limit = rng() % 2 ? 0xFFFFFFFFu : 16u;
    const Recorder rec = receive(stream, 1 + rng() % 64, limit);
    for (const World& w : rec.frames) {
      const Bytes again = encode_frame(WireVersion::kV2, w);
      ASSERT_NE(std::search(stream.begin(), stream.end(), again.begin(), again.end()), stream.end());
    }
    (void)decode_frame(WireVersion::kV2, stream, limit);
  }
}

}  // namespace
}  // namespace tripsitter::link
