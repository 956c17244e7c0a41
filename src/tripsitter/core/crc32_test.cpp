#include <tripsitter/core/crc32.h>

#include <string_view>
#include <vector>

#include <gtest/gtest.h>

namespace tripsitter::core {
namespace {

std::vector<std::uint8_t> bytes_of(std::string_view s) { return {s.begin(), s.end()}; }

TEST(Crc32, MatchesTheStandardCheckValue) {
  EXPECT_EQ(crc32(bytes_of("123456789")), 0xCBF43926u);
  EXPECT_EQ(crc32(bytes_of("")), 0u);
}

TEST(Crc32, ContinuesAcrossPieces) {
  const auto all = bytes_of("The quick brown fox jumps over the lazy dog");
  EXPECT_EQ(crc32(all), 0x414FA339u);
  const std::span<const std::uint8_t> s(all);
  for (std::size_t cut = 0; cut <= all.size(); ++cut)
    EXPECT_EQ(crc32(s.subspan(cut), crc32(s.first(cut))), 0x414FA339u) << cut;
}

}  // namespace
}  // namespace tripsitter::core
