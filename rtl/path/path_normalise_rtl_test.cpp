// The normalisation of a scattered direction (ts_path_normalise.sv) held to the model, artix::unit_direction
// (approx::unit at 17 bits, saturated), bit for bit: directions of every length the scatter unit gives (v.v from 64,
// the shortest the model normalises, to components of 2^19), along the axes and anywhere, a direction a cycle and
// with gaps, every bin of the reciprocal square root's table reached.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <deque>
#include <memory>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_path_normalise.h>

#include <tripsitter/device/approx.h>
#include <tripsitter/device/artix_path.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;
namespace approx = device::approx;

constexpr int kLatency = 15;

// The table bin approx::unit reads for v: m's top byte, m = v.v 2^(-2k) in [2^30, 2^32).
int table_bin(const approx::Unit3& v) {
  const auto s = static_cast<std::uint64_t>(v.x * v.x + v.y * v.y + v.z * v.z);
  const int e = std::bit_width(s) - 31;
  const int k = e >= 0 ? e / 2 : -((1 - e) / 2);
  const std::uint64_t m = k >= 0 ? s >> (2 * k) : s << (-2 * k);
  return static_cast<int>(m >> 24);
}

TEST(PathNormaliseRtl, DirectionsEqualTheModel) {
  std::mt19937_64 rng(20261207);
  const auto below = [&](std::int64_t n) { return static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(n)); };
  auto top = std::make_unique<Vts_path_normalise>();
  top->rst = 1;
  rising_edge(*top);
  top->rst = 0;
  struct Want {
    std::int64_t cycle;
    artix::Vec3i d;
    std::uint32_t tag;
  };
  std::deque<Want> want;
  std::set<int> bins;
  std::int64_t now = 0;
  int checked = 0, saturated = 0;
  const auto check = [&] {
    if (top->out_valid == 0) return;
    ASSERT_FALSE(want.empty()) << "a result with nothing in flight, cycle " << now;
    const Want w = want.front();
    want.pop_front();
    EXPECT_EQ(now, w.cycle);
    EXPECT_EQ(top->out_tag, w.tag);
    artix::Vec3i got{};
    for (std::size_t k = 0; k < 3; ++k)
      got[k] = static_cast<std::int64_t>(sign_extend(get(top->out_d) >> (18 * static_cast<int>(k)), 18));
    EXPECT_EQ(got, w.d) << "direction " << w.tag;
    ++checked;
  };
  constexpr int kDirections = 60000;
  for (int i = 0; i < kDirections;) {
    approx::Unit3 v{};
    const int kind = static_cast<int>(below(8));
    const std::int64_t reach = std::int64_t{1} << (3 + below(17));  // up to 2^19
    if (kind == 0) {  // along an axis, either way
      const std::int64_t a = 8 + below(reach);
      (below(3) == 0 ? v.x : below(2) == 0 ? v.y : v.z) = below(2) == 0 ? a : -a;
    } else if (kind == 1) {  // near the shortest the model normalises
      v = {below(9) - 4, below(9) - 4, below(9) - 4};
    } else {
      v = {below(2 * reach) - reach, below(2 * reach) - reach, below(2 * reach) - reach};
    }
    if (v.x * v.x + v.y * v.y + v.z * v.z < 64) continue;
    for (std::int64_t* c : {&v.x, &v.y, &v.z}) *c = std::clamp<std::int64_t>(*c, -(1 << 19) + 1, (1 << 19) - 1);
    bins.insert(table_bin(v));
    const artix::Vec3i d = artix::unit_direction(v);
    for (const auto c : d) saturated += c == artix::kDirectionMax || c == -artix::kDirectionMax;
    top->in_valid = 1;
    const UInt128 packed = (static_cast<UInt128>(v.x) & 0xffffff) | (static_cast<UInt128>(v.y) & 0xffffff) << 24 |
                           (static_cast<UInt128>(v.z) & 0xffffff) << 48;
    put(top->in_v, packed);
    top->in_tag = static_cast<std::uint32_t>(i);
    want.push_back({now + kLatency, d, static_cast<std::uint32_t>(i)});
    ++i;
    check();
    rising_edge(*top);
    ++now;
    top->in_valid = 0;
    for (int gap = below(6) == 0 ? static_cast<int>(below(20)) : 0; gap > 0; --gap) {
      check();
      rising_edge(*top);
      ++now;
    }
  }
  for (int i = 0; i < kLatency + 2; ++i) {
    check();
    rising_edge(*top);
    ++now;
  }
  EXPECT_TRUE(want.empty());
  EXPECT_EQ(checked, kDirections);
  EXPECT_EQ(bins.size(), 192u) << "every bin of the table (m's top byte 64 .. 255)";
  EXPECT_GT(saturated, 100);
}

}  // namespace
}  // namespace tripsitter::rtl
