// Tests of what v3 adds to the framed wire: the header's own CRC, the session, and the recovery bound of
// docs/link_format.md ("Why one damaged byte costs one world"): after any single damaged, lost, inserted or
// duplicated byte the decoder loses at most the frame that held it, and delivers each following intact frame
// the moment its last byte arrives. The codec's behaviour shared with v2 is tested in frame_test.cpp.
#include <tripsitter/link/frame.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <tripsitter/core/crc32.h>

namespace tripsitter::link {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr std::uint32_t kMaxSpheres = 4096;

World world_of(std::uint32_t session, std::uint32_t sequence, std::size_t spheres, std::mt19937& rng) {
  World w;
  w.session = session;
  w.sequence = sequence;
  w.frac_bits = 4;
  for (std::size_t i = 0; i < spheres; ++i) {
    WireSphere s;
    // Coordinates of a scene in view, as a host sends them: small numbers, so most bytes are 0x00 or 0xFF.
    s.x = static_cast<std::int32_t>(rng() % (1u << 20));
    s.y = static_cast<std::int32_t>(rng() % (1u << 20)) - (1 << 19);
    s.z = static_cast<std::int32_t>(rng() % (1u << 20));
    s.radius = 1 + rng() % 100000;
    s.material = static_cast<std::uint8_t>(rng() % 3);
    s.albedo = {static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng())};
    s.fuzz = static_cast<std::uint16_t>(rng());
    s.ior = static_cast<std::uint16_t>(1 + rng() % 65535);
    w.spheres.push_back(s);
  }
  return w;
}

// Frames as the stream decoder delivers them, with the number of input bytes pushed when each came out.
struct Delivery {
  World world;
  std::size_t after_bytes;
};

struct Decoded {
  std::vector<Delivery> frames;
  std::vector<FrameError> errors;
  std::size_t most_buffered = 0;
};

// Pushes the stream one byte at a time, so the moment of each delivery is exact.
Decoded decode_bytewise(WireVersion wire, const Bytes& stream, std::uint32_t limit = kMaxSpheres) {
  Decoded d;
  std::size_t pushed = 0;
  FrameStreamDecoder decoder(wire, limit,
                             {[&](World&& w) { d.frames.push_back({std::move(w), pushed}); },
                              [&](const FrameFailure& f, std::size_t) { d.errors.push_back(f.error); }});
  for (const std::uint8_t b : stream) {
    ++pushed;
    decoder.push(std::span<const std::uint8_t>(&b, 1));
    d.most_buffered = std::max(d.most_buffered, decoder.buffered_bytes());
  }
  decoder.end_of_stream();
  return d;
}

TEST(WireV3, WorkedExampleOfTheDocument) {
  World w;
  w.session = 42;
  w.sequence = 1;
  w.frac_bits = 4;
  WireSphere s;
  s.z = 400 * 16;
  s.radius = 64 * 16;
  s.albedo = {204, 77, 77};
  s.ior = 6144;
  w.spheres.push_back(s);
  const Bytes expected = {0x54, 0x53, 0x57, 0x33, 0x03, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x2A, 0x00, 0x00,
                          0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x18, 0xB6, 0xE8, 0x5D, 0xF9,
                          0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x19, 0x00, 0x00, 0x00,
                          0x04, 0x00, 0x00, 0xCC, 0x4D, 0x4D, 0x00, 0x00, 0x18, 0x00, 0x2F, 0x7E, 0x9A, 0x59};
  EXPECT_EQ(encode_frame(WireVersion::kV3, w), expected);
  EXPECT_EQ(frame_bytes(WireVersion::kV3, 1), expected.size());
  const auto back = decode_frame(WireVersion::kV3, expected, kMaxSpheres);
  ASSERT_TRUE(back.ok()) << back.error().detail;
  EXPECT_EQ(back.value(), w);
}

TEST(WireV3, RoundTripOfRandomWorlds) {
  std::mt19937 rng(3);
  for (std::size_t n : {0u, 1u, 2u, 17u, 300u}) {
    const World w = world_of(static_cast<std::uint32_t>(rng()), static_cast<std::uint32_t>(rng()), n, rng);
    const Bytes bytes = encode_frame(WireVersion::kV3, w);
    ASSERT_EQ(bytes.size(), kV3HeaderBytes + n * kSphereBytes + kFrameTrailerBytes);
    const auto back = decode_frame(WireVersion::kV3, bytes, kMaxSpheres);
    ASSERT_TRUE(back.ok()) << back.error().detail;
    EXPECT_EQ(back.value(), w);
  }
}

TEST(WireV3, RestampGivesSessionAndSequenceAndKeepsBothCrcsRight) {
  std::mt19937 rng(5);
  const World w = world_of(0, 0, 3, rng);
  Bytes bytes = encode_frame(WireVersion::kV3, w);
  restamp_frame(WireVersion::kV3, bytes, 0xDEADBEEF, 77);
  World expected = w;
  expected.session = 0xDEADBEEF;
  expected.sequence = 77;
  EXPECT_EQ(bytes, encode_frame(WireVersion::kV3, expected));
  Bytes v2 = encode_frame(WireVersion::kV2, w);
  restamp_frame(WireVersion::kV2, v2, 0xDEADBEEF, 77);
  expected.session = 0;  // v2 has no session
  EXPECT_EQ(v2, encode_frame(WireVersion::kV2, expected));
}

TEST(WireV3, EveryDamagedHeaderByteIsRefusedAtTheHeaderNotAfterThePayload) {
  std::mt19937 rng(7);
  const Bytes good = encode_frame(WireVersion::kV3, world_of(9, 1, 2, rng));
  for (std::size_t at = 0; at < kV3HeaderBytes; ++at) {
    for (int bit = 0; bit < 8; ++bit) {
      Bytes bad = good;
      bad[at] ^= static_cast<std::uint8_t>(1u << bit);
      // Only the header goes in: whatever the damage, the decoder must already have refused it.
      const Bytes header(bad.begin(), bad.begin() + kV3HeaderBytes);
      const Decoded d = decode_bytewise(WireVersion::kV3, header);
      EXPECT_TRUE(d.frames.empty());
      ASSERT_FALSE(d.errors.empty()) << "byte " << at << " bit " << bit;
      EXPECT_NE(d.errors.front(), FrameError::kTruncated) << "byte " << at << " bit " << bit;
      EXPECT_NE(d.errors.front(), FrameError::kBadCrc) << "byte " << at << " bit " << bit;
    }
  }
}

TEST(WireV3, AHeaderAnnouncingFourGigabytesCostsNothing) {
  World w;
  w.session = 1;
  w.sequence = 1;
  Bytes bytes = encode_frame(WireVersion::kV3, w);
  // count 178,956,970 and its length, 4,294,967,280 bytes, with a header CRC that matches: an honest header.
  const std::uint32_t count = 178'956'970;
  const std::uint32_t length = count * 24;
  for (std::size_t k = 0; k < 4; ++k) {
    bytes[16 + k] = static_cast<std::uint8_t>(count >> (24 - 8 * k));
    bytes[20 + k] = static_cast<std::uint8_t>(length >> (24 - 8 * k));
  }
  const std::uint32_t crc = core::crc32(std::span<const std::uint8_t>(bytes).first(24));
  for (std::size_t k = 0; k < 4; ++k) bytes[24 + k] = static_cast<std::uint8_t>(crc >> (24 - 8 * k));
  const Decoded d = decode_bytewise(WireVersion::kV3, Bytes(bytes.begin(), bytes.begin() + kV3HeaderBytes));
  ASSERT_FALSE(d.errors.empty());
  EXPECT_EQ(d.errors.front(), FrameError::kTooManySpheres);
  EXPECT_LE(d.most_buffered, kV3HeaderBytes);
}

// The fault is applied to the second of four frames; the others must come out, each at the very byte that
// completes it (shifted by the bytes the fault added or removed before it).
struct Fault {
  std::string name;
  std::size_t at;
  int kind;  // 0 bit flip (bit = value), 1 drop, 2 insert (value), 3 duplicate
  std::uint8_t value;
};

Bytes with_fault(const Bytes& stream, const Fault& f) {
  Bytes out = stream;
  switch (f.kind) {
    case 0: out[f.at] ^= f.value; break;
    case 1: out.erase(out.begin() + static_cast<std::ptrdiff_t>(f.at)); break;
    case 2: out.insert(out.begin() + static_cast<std::ptrdiff_t>(f.at), f.value); break;
    default: out.insert(out.begin() + static_cast<std::ptrdiff_t>(f.at), out[f.at]); break;
  }
  return out;
}

// Runs every single-byte fault at every position of frame B in A B C D and returns how many faults lost a
// frame other than B, or delivered C or D later than the byte that completes it.
struct BoundResult {
  std::size_t faults = 0;
  std::size_t lost_others = 0;
  std::size_t late = 0;
};

BoundResult single_byte_faults(WireVersion wire) {
  std::mt19937 rng(11);
  std::vector<Bytes> frames;
  for (std::uint32_t i = 1; i <= 4; ++i) frames.push_back(encode_frame(wire, world_of(5, i, 3, rng)));
  Bytes stream;
  std::vector<std::size_t> ends;  // stream offset just after each frame
  for (const Bytes& f : frames) {
    stream.insert(stream.end(), f.begin(), f.end());
    ends.push_back(stream.size());
  }
  const std::size_t b_start = ends[0];
  BoundResult r;
  for (std::size_t at = b_start; at < ends[1]; ++at) {
    std::vector<Fault> faults;
    for (int bit = 0; bit < 8; ++bit) faults.push_back({"flip", at, 0, static_cast<std::uint8_t>(1u << bit)});
    faults.push_back({"drop", at, 1, 0});
    for (const std::uint8_t v : {std::uint8_t{0x00}, std::uint8_t{0xFF}, std::uint8_t{'T'}, std::uint8_t{0x18}})
      faults.push_back({"insert", at, 2, v});
    faults.push_back({"duplicate", at, 3, 0});
    for (const Fault& f : faults) {
      ++r.faults;
      const std::ptrdiff_t shift = f.kind == 1 ? -1 : f.kind >= 2 ? 1 : 0;
      const Decoded d = decode_bytewise(wire, with_fault(stream, f));
      std::vector<std::optional<std::size_t>> when(4);
      for (const Delivery& del : d.frames) {
        if (del.world.sequence >= 1 && del.world.sequence <= 4) when[del.world.sequence - 1] = del.after_bytes;
      }
      bool lost = false;
      bool late = false;
      for (std::size_t i : {0u, 2u, 3u}) {
        if (!when[i]) {
          lost = true;
          continue;
        }
        const std::size_t due = i == 0 ? ends[0] : static_cast<std::size_t>(static_cast<std::ptrdiff_t>(ends[i]) + shift);
        if (*when[i] != due) late = true;
      }
      r.lost_others += lost;
      r.late += late;
    }
  }
  return r;
}

TEST(WireV3, ASingleByteFaultCostsAtMostTheFrameThatHeldIt) {
  const BoundResult r = single_byte_faults(WireVersion::kV3);
  EXPECT_GT(r.faults, 1000u);
  EXPECT_EQ(r.lost_others, 0u);
  EXPECT_EQ(r.late, 0u) << "every following intact frame comes out the moment it is complete";
}

// The reason for v3: on v2 a byte lost inside the header shifts a plausible count and length into place
// (count x 256 and length x 256 still agree when the next byte is 0), and the frames after it are read as the
// damaged frame's payload: late, or, when the stream ends first as here, lost.
TEST(WireV3, OnV2TheSameFaultsCostTheFramesAfterTheDamagedOne) {
  const BoundResult r = single_byte_faults(WireVersion::kV2);
  EXPECT_GT(r.lost_others + r.late, 0u);
}

// A host that restarts in the middle of a world (SPI has no disconnect to tell the device): the cut frame is
// dropped as soon as the next frame's header is whole, and the next frame comes out the moment it is complete.
TEST(WireV3, AFrameCutByANewHeaderIsDroppedAtOnce) {
  std::mt19937 rng(17);
  const Bytes a = encode_frame(WireVersion::kV3, world_of(1, 1, 100, rng));
  const Bytes b = encode_frame(WireVersion::kV3, world_of(2, 1, 3, rng));
  for (const std::size_t cut : {kV3HeaderBytes, kV3HeaderBytes + 1, a.size() / 2, a.size() - 1}) {
    Bytes stream(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(cut));
    stream.insert(stream.end(), b.begin(), b.end());
    const Decoded d = decode_bytewise(WireVersion::kV3, stream);
    ASSERT_EQ(d.frames.size(), 1u) << "cut at " << cut;
    EXPECT_EQ(d.frames[0].world.session, 2u);
    EXPECT_EQ(d.frames[0].after_bytes, stream.size());
    ASSERT_FALSE(d.errors.empty());
    // Cut one byte short, the frame is complete with the new frame's first byte and fails its CRC first.
    EXPECT_EQ(d.errors[0], cut == a.size() - 1 ? FrameError::kBadCrc : FrameError::kTruncated) << "cut at " << cut;
  }
  // On v2 the new frame is read as the cut frame's payload, and it could come out only once as many bytes as
  // the cut frame announced had arrived: here the stream ends first, and it never does.
  const Bytes a2 = encode_frame(WireVersion::kV2, world_of(0, 1, 100, rng));
  const Bytes b2 = encode_frame(WireVersion::kV2, world_of(0, 1, 3, rng));
  Bytes stream(a2.begin(), a2.begin() + 40);
  stream.insert(stream.end(), b2.begin(), b2.end());
  EXPECT_TRUE(decode_bytewise(WireVersion::kV2, stream).frames.empty());
}

// An intact header inside a frame's payload cuts the frame there, whether the frame arrives whole or in
// pieces: the rule looks at the frame's bytes only (decode_frame agrees).
TEST(WireV3, AHeaderInsideAFrameCutsItHoweverTheFrameArrives) {
  std::mt19937 rng(19);
  World carrier = world_of(1, 1, 4, rng);
  Bytes outer = encode_frame(WireVersion::kV3, carrier);
  const Bytes inner = encode_frame(WireVersion::kV3, world_of(2, 1, 0, rng));  // 32 bytes: header and CRC
  std::copy(inner.begin(), inner.begin() + kV3HeaderBytes, outer.begin() + kV3HeaderBytes + 24);
  restamp_frame(WireVersion::kV3, outer, 1, 1);  // a frame CRC that matches: the host really sent this
  const auto whole = decode_frame(WireVersion::kV3, outer, kMaxSpheres);
  ASSERT_FALSE(whole.ok());
  EXPECT_EQ(whole.error().error, FrameError::kTruncated);
  EXPECT_EQ(whole.error().offset, kV3HeaderBytes + 24);
  for (const std::size_t transfer : {std::size_t{1}, std::size_t{7}, outer.size()}) {
    std::vector<World> frames;
    std::vector<FrameError> errors;
    FrameStreamDecoder decoder(WireVersion::kV3, kMaxSpheres,
                               {[&](World&& w) { frames.push_back(std::move(w)); },
                                [&](const FrameFailure& f, std::size_t) { errors.push_back(f.error); }});
    for (std::size_t at = 0; at < outer.size(); at += transfer)
      decoder.push(std::span<const std::uint8_t>(outer).subspan(at, std::min(transfer, outer.size() - at)));
    decoder.end_of_stream();
    EXPECT_TRUE(frames.empty()) << "transfers of " << transfer;
    ASSERT_FALSE(errors.empty());
    EXPECT_EQ(errors.front(), FrameError::kTruncated) << "transfers of " << transfer;
  }
}

TEST(WireV3, AV2FrameIsNoiseToAV3DecoderAndTheOtherWayRound) {
  std::mt19937 rng(13);
  const World w = world_of(3, 1, 2, rng);
  const Decoded on_v3 = decode_bytewise(WireVersion::kV3, encode_frame(WireVersion::kV2, w));
  EXPECT_TRUE(on_v3.frames.empty());
  ASSERT_EQ(on_v3.errors.size(), 1u);
  EXPECT_EQ(on_v3.errors[0], FrameError::kBadMagic);
  const Decoded on_v2 = decode_bytewise(WireVersion::kV2, encode_frame(WireVersion::kV3, w));
  EXPECT_TRUE(on_v2.frames.empty());
}

}  // namespace
}  // namespace tripsitter::link
