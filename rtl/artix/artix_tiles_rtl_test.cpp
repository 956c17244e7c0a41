// The artix tile lists' RTL (ts_artix_tiles.sv) against artix::row_tiles, bit for bit, run as the lead runs it:
// a line's build pulsed at its start and the flip 3,200 cycles later, while the ports read back the lists built the
// line before, every tile's length and every entry through every read port. Worlds of cull bounds from random
// spheres (artix::cull_bounds, as artix::prepare_world makes them) and of random bounds, every row; the worst case
// (256 spheres spanning the screen: 5,120 entries) built within 3,000 cycles; and a world written while another is
// shown, then swapped in between frames. With the preset's 12 ports, and with 3 (an odd count: a half replica).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_artix_tiles.h>
#include <Vts_artix_tiles_n3.h>

#include <tripsitter/core/screen.h>
#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/artix_kernel.h>
#include <tripsitter/device/artix_units.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;

constexpr int kTiles = 20;         // ts_artix_pkg::Tiles
constexpr int kTileColumns = 32;   // ts_artix_pkg::TileColumns
constexpr int kMaxSpheres = 256;   // ts_artix_pkg::MaxSpheres
constexpr int kTileBits = 5;       // rd_tile's field
constexpr int kPosBits = 8;        // rd_pos's and rd_sphere's
constexpr int kCountBits = 9;      // rd_count's
constexpr int kLeadCycles = 3200;  // a line: the lead flips this long after the build
constexpr int kBuildBound = 3000;  // the build must end within this

using Bounds = std::vector<core::ScreenBounds>;

// The model's lists of a row of `bounds`.
artix::RowTiles expected_tiles(const Bounds& bounds, int row) {
  artix::UnitWorld world;
  world.bounds = bounds;  // row_tiles reads only the bounds
  return artix::row_tiles(world, row, kTileColumns);
}

// Multi-bit port fields: field i of `bits` bits.
template <class Port>
void put_field(Port& port, int i, int bits, UInt128 v) {
  UInt128 all = get(port);
  const UInt128 m = (UInt128{1} << bits) - 1;
  all = (all & ~(m << (bits * i))) | ((v & m) << (bits * i));
  put(port, all);
}
template <class Port>
int get_field(const Port& port, int i, int bits) {
  return static_cast<int>((get(port) >> (bits * i)) & ((UInt128{1} << bits) - 1));
}

// One Verilated tile-list block with `Ports` read ports, clocked by hand, driven as the lead drives it.
template <class Model, int Ports>
class TilesRtl {
 public:
  TilesRtl() {
    context_.randReset(2);  // random initial values: the reset must make them irrelevant
    top_ = std::make_unique<Model>(&context_);
    top_->rst = 1;
    top_->we = 0;
    top_->swap = 0;
    top_->build = 0;
    top_->flip = 0;
    for (int i = 0; i < 3; ++i) tick();
    top_->rst = 0;
    tick();
  }

  // Writes a world's bounds into the back copy, a sphere a cycle (the RTL takes them at any pace).
  void write(const Bounds& bounds) {
    for (std::size_t i = 0; i < bounds.size(); ++i) write_one(static_cast<int>(i), bounds[i]);
    top_->we = 0;
  }
  void swap() {
    top_->swap = 1;
    tick();
    top_->swap = 0;
  }

  // One line as the lead runs it: in its first cycle `build` for `row` over the front copy's first `count` spheres
  // and, when a build came before (`shown`), `flip`, which makes that build's lists the ones read; then 3,200
  // cycles (more if the reads need them) in which every port reads back every entry and length of `shown`, and
  // `back` (spheres of the next world, if any) is written into the back copy. The reads of the first cycle still see
  // the lists read before the flip, `before`. Returns the mismatches read; sets `build_cycles` to the cycles busy
  // was high.
  int line(int row, int count, const artix::RowTiles* shown, const artix::RowTiles* before, const Bounds* back,
           int& build_cycles) {
    top_->build = 1;
    top_->build_row = static_cast<SData>(row);
    top_->build_count = static_cast<SData>(count);
    top_->flip = shown != nullptr;
    const std::vector<std::pair<int, int>> reads = every_read(shown);
    const std::vector<std::pair<int, int>> reads_before = every_read(before);
    const int m = static_cast<int>(reads.size());
    int bad = 0;
    build_cycles = 0;
    bool built = false;
    std::vector<std::pair<int, int>> asked(Ports);
    std::size_t next_write = 0;
    for (int cycle = 0; cycle < kLeadCycles || cycle <= m || !built; ++cycle) {
      if (cycle > 4 * kLeadCycles + m) {
        ADD_FAILURE() << "row " << row << ": the build never ended";
        return bad + 1;
      }
      // Port p walks through all of the reads, starting p strides in.
      const auto& now = cycle == 0 ? reads_before : reads;
      const int n = static_cast<int>(now.size());
      const int k = cycle == 0 ? 0 : cycle - 1;
      for (int p = 0; p < Ports; ++p) {
        const auto i = static_cast<std::size_t>(p);
        asked[i] =
            k < n ? now[static_cast<std::size_t>((k + p * (n / Ports + 1)) % n)]
                  : std::pair<int, int>{static_cast<int>(junk_() % kTiles), static_cast<int>(junk_() % kMaxSpheres)};
        put_field(top_->rd_tile, p, kTileBits, static_cast<UInt128>(asked[i].first));
        put_field(top_->rd_pos, p, kPosBits, static_cast<UInt128>(asked[i].second));
      }
      if (back && next_write < back->size() && junk_() % 3 == 0) {
        put_write(static_cast<int>(next_write), (*back)[next_write]);
        ++next_write;
      } else {
        top_->we = 0;
      }
      tick();
      top_->build = 0;
      top_->flip = 0;
      // The reads asked in this cycle, registered.
      if (k < n)
        for (int p = 0; p < Ports; ++p)
          bad += check(cycle == 0 ? *before : *shown, p, asked[static_cast<std::size_t>(p)]);
      if (top_->busy) ++build_cycles;
      built = !top_->busy;
    }
    top_->we = 0;
    if (back) {  // what is left of the next world
      for (; next_write < back->size(); ++next_write) write_one(static_cast<int>(next_write), (*back)[next_write]);
      top_->we = 0;
    }
    return bad;
  }

 private:
  // Every (tile, position) of `tiles`, and position 0 of the empty lists for their length.
  static std::vector<std::pair<int, int>> every_read(const artix::RowTiles* tiles) {
    std::vector<std::pair<int, int>> reads;
    if (tiles)
      for (int t = 0; t < kTiles; ++t)
        for (int pos = 0; pos < std::max<int>(1, static_cast<int>(tiles->list(t).size())); ++pos)
          reads.push_back({t, pos});
    return reads;
  }

  void write_one(int i, const core::ScreenBounds& b) {
    put_write(i, b);
    tick();
  }
  void put_write(int i, const core::ScreenBounds& b) {
    top_->we = 1;
    top_->waddr = static_cast<CData>(i);
    top_->wempty = b.col_lo > b.col_hi || b.row_lo > b.row_hi;
    top_->wcol_lo = static_cast<SData>(top_->wempty ? junk_() % 1024 : static_cast<unsigned>(b.col_lo));
    top_->wcol_hi = static_cast<SData>(top_->wempty ? junk_() % 1024 : static_cast<unsigned>(b.col_hi));
    top_->wrow_lo = static_cast<SData>(top_->wempty ? junk_() % 512 : static_cast<unsigned>(b.row_lo));
    top_->wrow_hi = static_cast<SData>(top_->wempty ? junk_() % 512 : static_cast<unsigned>(b.row_hi));
  }

  int check(const artix::RowTiles& shown, int p, std::pair<int, int> asked) {
    const auto [tile, pos] = asked;
    const std::span<const int> list = shown.list(tile);
    const int count = get_field(top_->rd_count, p, kCountBits);
    if (count != static_cast<int>(list.size())) {
      if (++reported_ <= 10)
        ADD_FAILURE() << "port " << p << ", tile " << tile << ": length " << count << ", model " << list.size();
      return 1;
    }
    if (pos >= count) return 0;
    const int sphere = get_field(top_->rd_sphere, p, kPosBits);
    if (sphere != list[static_cast<std::size_t>(pos)]) {
      if (++reported_ <= 10)
        ADD_FAILURE() << "port " << p << ", tile " << tile << ", position " << pos << ": sphere " << sphere
                      << ", model " << list[static_cast<std::size_t>(pos)];
      return 1;
    }
    return 0;
  }

  void tick() {
    rising_edge(*top_);
  }

  VerilatedContext context_;
  std::unique_ptr<Model> top_;
  std::mt19937_64 junk_{77};
  int reported_ = 0;
};

// ---- worlds --------------------------------------------------------------------------------------------------------

// Cull bounds of random spheres, as artix::prepare_world gives them: centres mostly in front and in view, radii
// log-uniform, so that lists of every length occur.
Bounds cull_world(std::mt19937_64& rng, int n) {
  const auto log_uniform = [&rng](double max) {
    return std::exp(std::uniform_real_distribution<double>(0, std::log(max))(rng));
  };
  const auto uniform = [&rng](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  Bounds b;
  for (int i = 0; i < n; ++i) {
    const double z = rng() % 10 == 0 ? -log_uniform(1 << 20) : log_uniform(1 << 20);
    const double zz = std::abs(z);
    const std::int64_t r = std::clamp<std::int64_t>(static_cast<std::int64_t>(log_uniform(zz)), 1, (1 << 21) - 1);
    core::KernelSphere<std::int64_t> s{
        {static_cast<std::int64_t>(zz * uniform(-1.3, 1.3)), static_cast<std::int64_t>(zz * uniform(-1.0, 1.0)),
         static_cast<std::int64_t>(z)},
        r};
    b.push_back(artix::cull_bounds(artix::prepare_sphere(s, core::KernelSurface{})));
  }
  return b;
}

// Random bounds: any columns and rows, some empty.
Bounds random_world(std::mt19937_64& rng, int n) {
  Bounds b;
  for (int i = 0; i < n; ++i) {
    if (rng() % 8 == 0) {
      b.push_back({});
      continue;
    }
    int c0 = static_cast<int>(rng() % 640), c1 = static_cast<int>(rng() % 640);
    int r0 = static_cast<int>(rng() % 480), r1 = static_cast<int>(rng() % 480);
    if (rng() % 2) c1 = std::min(639, c0 + static_cast<int>(rng() % 40));  // narrow ones too
    if (rng() % 2) r1 = std::min(479, r0 + static_cast<int>(rng() % 40));
    b.push_back({std::min(c0, c1), std::max(c0, c1), std::min(r0, r1), std::max(r0, r1)});
  }
  return b;
}

// Every row of `bounds` as the lead builds and shows them, after the world is written and swapped in. Returns the
// mismatches; `max_build` is the longest build.
template <class Model, int Ports>
int every_row(TilesRtl<Model, Ports>& rtl, const Bounds& bounds, int& max_build) {
  rtl.write(bounds);
  rtl.swap();
  int bad = 0;
  max_build = 0;
  artix::RowTiles shown, before;                          // the lists built on the last line, and on the one before
  for (int row = 0; row <= core::kScreenHeight; ++row) {  // one line more: the last row's lists are read on it
    int cycles = 0;
    const int build_row = std::min(row, core::kScreenHeight - 1);
    bad += rtl.line(build_row, static_cast<int>(bounds.size()), row > 0 ? &shown : nullptr, row > 1 ? &before : nullptr,
                    nullptr, cycles);
    max_build = std::max(max_build, cycles);
    before = shown;
    shown = expected_tiles(bounds, build_row);
  }
  return bad;
}

std::size_t entries(const Bounds& bounds) {
  std::size_t n = 0;
  for (int row = 0; row < core::kScreenHeight; ++row) n += expected_tiles(bounds, row).spheres.size();
  return n;
}

// ---- tests -------------------------------------------------------------------------------------------------------

TEST(ArtixTilesRtl, CullWorldsEveryRowEqualTheModel) {
  std::mt19937_64 rng(11);
  TilesRtl<Vts_artix_tiles, 12> rtl;
  for (const int n : {256, 100, 1}) {
    const Bounds bounds = cull_world(rng, n);
    // The world makes lists of every kind: long and short, and rows with none.
    const std::size_t total = entries(bounds);
    if (n == 256) {
      EXPECT_GT(total, 50000u);
    }
    int max_build = 0;
    EXPECT_EQ(every_row(rtl, bounds, max_build), 0) << n << " spheres";
    EXPECT_EQ(max_build, 10 * n + 2);
  }
}

TEST(ArtixTilesRtl, RandomBoundsEveryRowEqualTheModel) {
  std::mt19937_64 rng(12);
  TilesRtl<Vts_artix_tiles, 12> rtl;
  for (const int n : {256, 37}) {
    const Bounds bounds = random_world(rng, n);
    int max_build = 0;
    EXPECT_EQ(every_row(rtl, bounds, max_build), 0) << n << " spheres";
  }
}

TEST(ArtixTilesRtl, ThreePortsEqualTheModel) {
  std::mt19937_64 rng(13);
  TilesRtl<Vts_artix_tiles_n3, 3> rtl;
  const Bounds bounds = random_world(rng, 200);
  int max_build = 0;
  EXPECT_EQ(every_row(rtl, bounds, max_build), 0);
}

// 256 spheres spanning the whole screen: every list holds every sphere, 5,120 entries a row.
TEST(ArtixTilesRtl, TheWorstCaseIsBuiltWithinTheBound) {
  TilesRtl<Vts_artix_tiles, 12> rtl;
  const Bounds bounds(kMaxSpheres, core::ScreenBounds{0, 639, 0, 479});
  rtl.write(bounds);
  rtl.swap();
  int cycles = 0;
  EXPECT_EQ(rtl.line(0, kMaxSpheres, nullptr, nullptr, nullptr, cycles), 0);
  EXPECT_LE(cycles, kBuildBound);
  EXPECT_EQ(cycles, 2562);
  const artix::RowTiles full = expected_tiles(bounds, 0);
  ASSERT_EQ(full.spheres.size(), static_cast<std::size_t>(kTiles * kMaxSpheres));
  EXPECT_EQ(rtl.line(479, kMaxSpheres, &full, nullptr, nullptr, cycles), 0);
  EXPECT_LE(cycles, kBuildBound);
  EXPECT_EQ(rtl.line(479, kMaxSpheres, &full, &full, nullptr, cycles), 0);
}

// A world of no spheres (build_count 0) over a copy that holds spheres: every list is empty.
TEST(ArtixTilesRtl, AWorldOfNoSpheresHasEmptyLists) {
  TilesRtl<Vts_artix_tiles, 12> rtl;
  rtl.write(Bounds(3, core::ScreenBounds{0, 639, 0, 479}));
  rtl.swap();
  const artix::RowTiles none = expected_tiles({}, 100);
  ASSERT_TRUE(none.spheres.empty());
  int cycles = 0;
  EXPECT_EQ(rtl.line(100, 0, nullptr, nullptr, nullptr, cycles), 0);
  EXPECT_EQ(cycles, 12);
  EXPECT_EQ(rtl.line(101, 0, &none, nullptr, nullptr, cycles), 0);
}

// A world is written into the back copy while another is shown; the swap between frames brings it in, and
// neither frame sees the other's spheres.
TEST(ArtixTilesRtl, AWorldSwappedInBetweenFramesReplacesTheShownOne) {
  std::mt19937_64 rng(14);
  TilesRtl<Vts_artix_tiles, 12> rtl;
  const Bounds first = cull_world(rng, 256);
  const Bounds second = random_world(rng, 180);
  rtl.write(first);
  rtl.swap();
  int cycles = 0;
  int bad = 0;
  artix::RowTiles shown, before;
  // The first frame's rows, with the second world arriving meanwhile.
  for (int row = 0; row < core::kScreenHeight; row += 7) {
    bad += rtl.line(row, static_cast<int>(first.size()), row > 0 ? &shown : nullptr, row > 7 ? &before : nullptr,
                    row == 14 ? &second : nullptr, cycles);
    before = shown;
    shown = expected_tiles(first, row);
  }
  rtl.swap();  // vertical blanking
  for (int row = 0; row < core::kScreenHeight; row += 5) {
    bad += rtl.line(row, static_cast<int>(second.size()), &shown, &before, nullptr, cycles);
    before = shown;
    shown = expected_tiles(second, row);
  }
  bad += rtl.line(0, static_cast<int>(second.size()), &shown, &before, nullptr, cycles);
  EXPECT_EQ(bad, 0);
  // The two worlds' lists differ, so a copy mixed up would show.
  EXPECT_NE(expected_tiles(first, 240).spheres, expected_tiles(second, 240).spheres);
}

}  // namespace
}  // namespace tripsitter::rtl
