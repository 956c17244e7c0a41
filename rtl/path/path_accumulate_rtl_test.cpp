// The accumulation's RTL (ts_path_accumulate.sv) against the model's path_pixel() (device/path_kernel.h), bit for
// bit: pixels whose stored entries are of this world's epoch or another's, empty, partly and nearly full (so that
// some have converged and trace nothing), frames of 1 to 16 samples, lights from 0 to exactly 1 (the channel's clamp
// at 511 among them); each pixel's frame run through the block as the device would (open with the first sample,
// adds, close with the last; open alone for a converged pixel), its entry fed back each cycle, and the entry left in
// frame memory compared with the model's.
#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "path_rtl_util.h"

#include <Vts_path_accumulate.h>

#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/path_kernel.h>

namespace tripsitter::rtl {
namespace {

using Light = std::array<std::int64_t, 3>;

TEST(PathAccumulateRtl, EveryPixelsEntryIsTheModels) {
  std::mt19937_64 rng(91);
  VerilatedContext context;
  auto top = path::reset_model<Vts_path_accumulate>(context);
  int bad = 0, converged = 0, reopened = 0, clamped = 0;
  for (int pixel = 0; pixel < 20000; ++pixel) {
    device::PathFrame frame;
    frame.epoch = static_cast<std::uint8_t>(rng() % device::kEpochs);
    frame.spp = 1 + static_cast<int>(rng() % (rng() % 4 == 0 ? 16 : 3));
    frame.frame = static_cast<std::uint32_t>(rng() % 100);
    device::AccumEntry stored;
    stored.epoch = rng() % 4 == 0 ? static_cast<std::uint8_t>(rng() % device::kEpochs) : frame.epoch;
    const auto kind = rng() % 4;
    stored.count = kind == 0 ? 0 : kind == 1 ? static_cast<std::uint8_t>(255 - rng() % 20) : static_cast<std::uint8_t>(rng() % 256);
    for (auto& s : stored.sum) s = static_cast<std::uint32_t>(rng() % (511u * stored.count + 1));
    std::vector<Light> lights(static_cast<std::size_t>(frame.spp));
    for (Light& l : lights)
      for (auto& c : l) c = rng() % 6 == 0 ? 65536 - static_cast<std::int64_t>(rng() % 64) : static_cast<std::int64_t>(rng() % 65537);
    std::size_t next = 0;
    const device::PathPixel want = device::path_pixel(device::artix::path_arith(), 5, 7, stored, frame, [&](device::PathRng&) {
      device::PathSample s;
      s.light = lights[next++];
      return s;
    });
    const bool traced = next > 0;
    converged += !traced;
    reopened += stored.epoch != frame.epoch;
    for (const Light& l : lights)
      for (const auto c : l) clamped += traced && ((c + 64) >> 7) > 511;
    // The block: open with the first sample (or alone), adds, close with the last.
    std::uint64_t entry = path::pack(stored);
    const auto op = [&](bool open, bool add, bool close, const Light& l) {
      top->in_valid = 1;
      top->in_open = open;
      top->in_add = add;
      top->in_close = close;
      top->in_entry = entry;
      top->in_epoch = frame.epoch;
      top->in_spp = static_cast<CData>(frame.spp);
      UInt128 light = 0;
      for (int k = 0; k < 3; ++k) light |= static_cast<UInt128>(l[static_cast<std::size_t>(k)]) << (17 * k);
      put(top->in_light, light);
      top->in_tag = static_cast<SData>(pixel);
      rising_edge(*top);
      entry = top->out_entry;
      return top->out_traced != 0;
    };
    const bool rtl_traced = op(true, false, false, Light{});
    if (rtl_traced != traced && ++bad <= 3) ADD_FAILURE() << "pixel " << pixel << ": traced " << rtl_traced;
    if (rtl_traced) {
      for (int s = 0; s < frame.spp; ++s) op(false, true, s + 1 == frame.spp, lights[static_cast<std::size_t>(s)]);
    }
    const device::AccumEntry got = path::unpack_entry(entry);
    if (!(got == want.entry) && ++bad <= 3) {
      ADD_FAILURE() << "pixel " << pixel << ": rtl count " << int{got.count} << " epoch " << int{got.epoch} << " sums "
                    << got.sum[0] << " " << got.sum[1] << " " << got.sum[2] << "; model " << int{want.entry.count}
                    << " " << int{want.entry.epoch} << " " << want.entry.sum[0] << " " << want.entry.sum[1] << " "
                    << want.entry.sum[2];
    }
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(converged, 500);
  EXPECT_GT(reopened, 2000);
  EXPECT_GT(clamped, 500);
}

}  // namespace
}  // namespace tripsitter::rtl
