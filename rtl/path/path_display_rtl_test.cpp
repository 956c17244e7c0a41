// The display's RTL (ts_path_display.sv) against the model's display_colour() (device/frame_memory.h), bit for bit:
// every entry of the sRGB table (count 1, each mean 0..511 at every Bayer threshold), every count's reciprocal with the
// largest sums it can hold, random entries of every count (0 among them: black), each of the 16 Bayer positions,
// with dithering and without; each colour 3 cycles later with its tag.
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "path_rtl_util.h"

#include <Vts_path_display.h>

namespace tripsitter::rtl {
namespace {

struct Pixel {
  device::AccumEntry entry;
  int col = 0, row = 0;
  bool dither = true;
};

core::Rgb444 model(const Pixel& p) {
  return p.entry.count > 0 ? device::display_colour(p.entry, p.col, p.row, p.dither) : core::kBlack;
}

Pixel random_pixel(std::mt19937_64& rng, int count) {
  Pixel p;
  p.entry.count = static_cast<std::uint8_t>(count);
  p.entry.epoch = static_cast<std::uint8_t>(rng() % device::kEpochs);
  const std::uint32_t most = static_cast<std::uint32_t>(511 * count);
  for (auto& s : p.entry.sum) s = rng() % 8 == 0 ? most : static_cast<std::uint32_t>(rng() % (most + 1));
  p.col = static_cast<int>(rng() % 640);
  p.row = static_cast<int>(rng() % 480);
  p.dither = rng() % 2 == 0;
  return p;
}

std::vector<Pixel> pixels(std::mt19937_64& rng) {
  std::vector<Pixel> out;
  // The sRGB table: a mean of v on each channel (count 1, sum v), at each of the 16 positions dithered (their
  // thresholds 0..15 tell every entry exactly: one off by one moves the channel at one of them) and once not.
  for (int v = 0; v < 512; ++v) {
    for (int at = 0; at <= 16; ++at) {
      Pixel p = random_pixel(rng, 1);
      p.entry.sum = {static_cast<std::uint32_t>(v), static_cast<std::uint32_t>(v), static_cast<std::uint32_t>(v)};
      p.col = at & 3;
      p.row = (at >> 2) & 3;
      p.dither = at < 16;
      out.push_back(p);
    }
  }
  // Each count's reciprocal, with full sums (mean 511 exactly: the clamp's edge) and random ones.
  for (int c = 1; c <= device::kMaxSamples; ++c) {
    Pixel full = random_pixel(rng, c);
    full.entry.sum = {511u * static_cast<std::uint32_t>(c), 511u * static_cast<std::uint32_t>(c), 0};
    out.push_back(full);
    for (int i = 0; i < 20; ++i) out.push_back(random_pixel(rng, c));
  }
  for (int i = 0; i < 20000; ++i) out.push_back(random_pixel(rng, static_cast<int>(rng() % 256)));
  return out;
}

TEST(PathDisplayRtl, EveryColourIsTheModelsBitForBit) {
  std::mt19937_64 rng(101);
  const std::vector<Pixel> items = pixels(rng);
  std::vector<Pixel> junk;
  for (int i = 0; i < 8; ++i) junk.push_back(random_pixel(rng, static_cast<int>(rng() % 256)));
  int black = 0;
  for (const Pixel& p : items) black += p.entry.count == 0;
  EXPECT_GT(black, 40);
  VerilatedContext context;
  auto top = path::reset_model<Vts_path_display>(context);
  const int bad = path::stream<Vts_path_display, Pixel, core::Rgb444>(
      *top, items, junk, 3, rng, [&](std::size_t) { return rng() % 5 != 0; },
      [](Vts_path_display& t, const Pixel& p) {
        t.in_entry = path::pack(p.entry);
        t.in_col = static_cast<CData>(p.col & 3);
        t.in_row = static_cast<CData>(p.row & 3);
        t.in_dither = p.dither;
      },
      [](Vts_path_display& t) { return core::Rgb444(static_cast<std::uint16_t>(t.out_rgb)); }, model);
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace tripsitter::rtl
