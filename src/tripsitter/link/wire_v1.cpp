#include <tripsitter/link/wire_v1.h>

namespace tripsitter::link {
namespace {

// Bit positions of the fields in the word (SPEC.md section B): each field is `width` bits whose least
// significant bit sits at `shift`.
struct Field {
  int shift;
  int width;
  constexpr std::uint64_t mask() const { return (std::uint64_t{1} << width) - 1; }
};

constexpr Field kX{48, 16};
constexpr Field kY{33, 15};
constexpr Field kZ{18, 15};
constexpr Field kR{12, 6};
constexpr Field kColour{0, 12};

static_assert(kX.width == kV1X.total_bits && kY.width == kV1Y.total_bits && kZ.width == kV1Z.total_bits);
static_assert(kX.shift + kX.width == 64 && kY.shift + kY.width == kX.shift && kZ.shift + kZ.width == kY.shift &&
              kR.shift + kR.width == kZ.shift && kColour.shift + kColour.width == kR.shift);

// Two's complement bits of `value`, cut to the field and moved into place.
constexpr std::uint64_t place(std::int64_t value, Field field) {
  return (static_cast<std::uint64_t>(value) & field.mask()) << field.shift;
}

constexpr std::uint64_t extract(std::uint64_t word, Field field) { return (word >> field.shift) & field.mask(); }

// Reads a field as a two's complement number of its width.
constexpr std::int32_t extract_signed(std::uint64_t word, Field field) {
  const std::uint64_t bits = extract(word, field);
  const std::uint64_t sign = std::uint64_t{1} << (field.width - 1);
  return static_cast<std::int32_t>(static_cast<std::int64_t>(bits ^ sign) - static_cast<std::int64_t>(sign));
}

}  // namespace

std::uint64_t encode_v1_word(const V1Sphere& sphere) {
  return place(sphere.x_raw, kX) | place(sphere.y_raw, kY) | place(sphere.z_raw, kZ) |
         place(sphere.radius_log2, kR) | place(sphere.colour, kColour);
}

V1Sphere decode_v1_word(std::uint64_t word) {
  V1Sphere sphere;
  sphere.x_raw = extract_signed(word, kX);
  sphere.y_raw = extract_signed(word, kY);
  sphere.z_raw = extract_signed(word, kZ);
  sphere.radius_log2 = static_cast<std::uint8_t>(extract(word, kR));
  sphere.colour = static_cast<std::uint16_t>(extract(word, kColour));
  return sphere;
}

void append_v1_bytes(std::uint64_t word, std::vector<std::uint8_t>& out) {
  for (int shift = 56; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(word >> shift));
}

void V1StreamDecoder::push(std::span<const std::uint8_t> bytes) {
  for (std::uint8_t byte : bytes) {
    word_ = (word_ << 8) | byte;
    if (++filled_ == kV1WordBytes) {
      const V1Sphere sphere = decode_v1_word(word_);
      reset();
      if (on_word_) on_word_(sphere);
    }
  }
}

}  // namespace tripsitter::link
