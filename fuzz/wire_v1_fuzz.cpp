// The v1 wire (link/wire_v1.h): the word codec and the stream decoder.
//
// Input: one control byte, then the byte stream. The control byte seeds the sizes of the transfers the
// stream is cut into (1..16 bytes each) and, when odd, asks for a chip-select reset at one transfer boundary.
//
// Checks:
//   - every 64-bit word decodes to fields inside the word's formats, and encodes back to the same word;
//   - a V1Sphere within the formats survives encode then decode unchanged;
//   - the stream decoder, fed the stream in transfers, yields exactly the words of the stream's aligned
//     8-byte groups, holds stream size % 8 bytes at the end, and after reset() starts counting afresh.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <tripsitter/link/wire_v1.h>

#include "check.h"

namespace {

using tripsitter::link::V1Sphere;
namespace link = tripsitter::link;

std::uint64_t read_word(std::span<const std::uint8_t> bytes) {
  std::uint64_t word = 0;
  for (std::size_t i = 0; i < link::kV1WordBytes; ++i) word = (word << 8) | bytes[i];
  return word;
}

bool within_formats(const V1Sphere& s) {
  return link::kV1X.contains(s.x_raw) && link::kV1Y.contains(s.y_raw) && link::kV1Z.contains(s.z_raw) &&
         s.radius_log2 <= link::kV1RadiusLog2Max && s.colour <= 0xFFF;
}

// Decodes `stream` as whole aligned words, the reference for the stream decoder.
std::vector<V1Sphere> words_of(std::span<const std::uint8_t> stream) {
  std::vector<V1Sphere> out;
  for (std::size_t at = 0; at + link::kV1WordBytes <= stream.size(); at += link::kV1WordBytes) {
    out.push_back(link::decode_v1_word(read_word(stream.subspan(at))));
  }
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint8_t control = data[0];
  const std::span<const std::uint8_t> stream(data + 1, size - 1);

  // The word codec, on every aligned word of the stream and on the word at every byte offset.
  std::vector<std::uint8_t> bytes;
  bytes.reserve(link::kV1WordBytes);
  for (std::size_t at = 0; at + link::kV1WordBytes <= stream.size(); ++at) {
    const std::uint64_t word = read_word(stream.subspan(at));
    const V1Sphere sphere = link::decode_v1_word(word);
    FUZZ_CHECK(within_formats(sphere), "decode_v1_word gave a field outside the word's formats");
    FUZZ_CHECK(link::encode_v1_word(sphere) == word, "encode(decode(word)) differs from the word");
    bytes.clear();
    link::append_v1_bytes(word, bytes);
    FUZZ_CHECK(bytes.size() == link::kV1WordBytes && std::equal(bytes.begin(), bytes.end(), stream.begin() + at),
               "append_v1_bytes does not give the word's bytes most significant first");
  }

  // A sphere built from the bytes, each field folded into its format, survives encode then decode.
  if (stream.size() >= 12) {
    const auto fold = [](std::uint32_t raw, const tripsitter::core::FixedFormat& f) {
      const std::int64_t span = f.max_raw() - f.min_raw() + 1;
      return static_cast<std::int32_t>(f.min_raw() + static_cast<std::int64_t>(raw % static_cast<std::uint64_t>(span)));
    };
    const auto u32 = [&](std::size_t at) {
      return (std::uint32_t{stream[at]} << 24) | (std::uint32_t{stream[at + 1]} << 16) |
             (std::uint32_t{stream[at + 2]} << 8) | stream[at + 3];
    };
    V1Sphere s;
    s.x_raw = fold(u32(0), link::kV1X);
    s.y_raw = fold(u32(4), link::kV1Y);
    s.z_raw = fold(u32(8), link::kV1Z);
    s.radius_log2 = static_cast<std::uint8_t>(stream[0] % (link::kV1RadiusLog2Max + 1));
    s.colour = static_cast<std::uint16_t>(u32(6) & 0xFFF);
    FUZZ_CHECK(link::decode_v1_word(link::encode_v1_word(s)) == s, "decode(encode(sphere)) differs from the sphere");
  }

  // The stream decoder, fed in transfers; an odd control byte resets it at one transfer boundary.
  std::vector<V1Sphere> got;
  link::V1StreamDecoder decoder([&](const V1Sphere& s) { got.push_back(s); });
  std::uint32_t state = control * 2654435761u + 1;
  const std::size_t reset_boundary = (control & 1) ? (control >> 1) % 8 : SIZE_MAX;
  std::size_t at = 0, reset_at = SIZE_MAX, boundary = 0;
  std::size_t words_before_reset = 0;
  while (at < stream.size()) {
    state = state * 1103515245u + 12345u;
    const std::size_t n = std::min<std::size_t>(1 + (state >> 16) % 16, stream.size() - at);
    decoder.push(stream.subspan(at, n));
    at += n;
    FUZZ_CHECK(decoder.pending_bytes() < link::kV1WordBytes, "pending_bytes() is not below a word");
    if (boundary++ == reset_boundary) {
      reset_at = at;
      words_before_reset = got.size();
      decoder.reset();
      FUZZ_CHECK(decoder.pending_bytes() == 0, "reset() left bytes pending");
    }
  }
  if (reset_at == SIZE_MAX) {
    FUZZ_CHECK(got == words_of(stream), "stream decoder words differ from the stream's aligned words");
    FUZZ_CHECK(decoder.pending_bytes() == stream.size() % link::kV1WordBytes, "wrong pending_bytes() at the end");
  } else {
    std::vector<V1Sphere> expected = words_of(stream.first(reset_at));
    FUZZ_CHECK(words_before_reset == expected.size(), "wrong number of words before the reset");
    const std::vector<V1Sphere> after = words_of(stream.subspan(reset_at));
    expected.insert(expected.end(), after.begin(), after.end());
    FUZZ_CHECK(got == expected, "after reset() the decoder does not count words from the reset");
    FUZZ_CHECK(decoder.pending_bytes() == (stream.size() - reset_at) % link::kV1WordBytes,
               "wrong pending_bytes() at the end (after a reset)");
  }
  return 0;
}
