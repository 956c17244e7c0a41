// A sphere's surface prepared for the path preset's bounce, as RTL (ts_path_surface.sv), held to path_surface bit for
// bit: every index of refraction the receiver takes (1024 .. 32768, u4.12) and some it refuses (clamped as the
// model clamps a word written directly), each with random materials, albedos and fuzz, started back to back (in the
// done cycle) and with gaps; every result the model's, in the done cycle 33 cycles after its start, alone.
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_path_surface.h>

#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/scene_memory.h>

namespace tripsitter::rtl {
namespace {

constexpr int kCycles = 33;

std::string describe(const device::PathSurface& s) {
  return "material " + std::to_string(s.material) + " albedo " + std::to_string(s.albedo[0]) + " " +
         std::to_string(s.albedo[1]) + " " + std::to_string(s.albedo[2]) + " fuzz " + std::to_string(s.fuzz) +
         " eta " + std::to_string(s.eta_enter) + " " + std::to_string(s.eta_leave) + " r0 " + std::to_string(s.r0) +
         " straight " + std::to_string(s.passes_straight);
}

TEST(PathSurfaceRtl, EverySupportedIndexOfRefractionAsTheModel) {
  std::mt19937_64 rng(20261207);
  std::vector<device::SurfaceWord> words;
  for (int ior = 0; ior <= 65535; ++ior) {
    if (ior >= 1000 && ior <= 32800 ? false : rng() % 64 != 0) continue;  // outside the range: a sample
    device::SurfaceWord w;
    w.material = static_cast<std::uint8_t>(rng() % 3);
    for (auto& a : w.albedo) a = static_cast<std::uint8_t>(rng());
    w.fuzz = static_cast<std::uint16_t>(rng());
    w.ior = static_cast<std::uint16_t>(ior);
    words.push_back(w);
  }
  for (int a = 0; a < 256; ++a) words[static_cast<std::size_t>(a)].albedo = {static_cast<std::uint8_t>(a), 0, 255};

  auto t = std::make_unique<Vts_path_surface>();
  t->rst = 1;
  t->start = 0;
  for (int i = 0; i < 3; ++i) rising_edge(*t);
  t->rst = 0;
  int bad = 0, straight = 0;
  std::size_t next = 0;
  std::int64_t cyc = 0, started = -1;
  const std::int64_t limit = 40 * static_cast<std::int64_t>(words.size()) + 100;
  device::PathSurface want;
  while ((next < words.size() || started >= 0) && cyc < limit) {
    t->eval();
    // The done cycle: alone, kCycles after the start, the model's surface.
    if (t->done != 0) {
      ASSERT_GE(started, 0) << "done with nothing started, cycle " << cyc;
      EXPECT_EQ(cyc - started, kCycles);
      device::PathSurface got;
      got.material = t->out_material;
      for (std::size_t k = 0; k < 3; ++k) got.albedo[k] = static_cast<std::uint32_t>((t->out_albedo >> (17 * k)) & 0x1FFFF);
      got.fuzz = t->out_fuzz;
      got.eta_enter = t->out_eta_enter;
      got.eta_leave = t->out_eta_leave;
      got.r0 = t->out_r0;
      got.passes_straight = t->out_straight != 0;
      const bool same = got.material == want.material && got.albedo == want.albedo && got.fuzz == want.fuzz &&
                        got.eta_enter == want.eta_enter && got.eta_leave == want.eta_leave && got.r0 == want.r0 &&
                        got.passes_straight == want.passes_straight;
      if (!same && ++bad <= 5) ADD_FAILURE() << "rtl " << describe(got) << "; model " << describe(want);
      straight += got.passes_straight;
      started = -1;
    } else {
      ASSERT_TRUE(started < 0 || cyc - started < kCycles) << "no done " << kCycles << " cycles after a start";
    }
    // A start when ready: in the done cycle (back to back) three times in four, else after a gap.
    t->start = 0;
    if (next < words.size() && t->ready != 0 && rng() % 4 != 0) {
      const device::SurfaceWord& w = words[next++];
      t->start = 1;
      t->in_material = w.material;
      t->in_albedo = static_cast<IData>(w.albedo[0] | w.albedo[1] << 8 | w.albedo[2] << 16);
      t->in_fuzz = w.fuzz;
      t->in_ior = w.ior;
      want = device::path_surface(w);
      started = cyc;
    } else if (t->ready == 0) {
      t->in_ior = static_cast<SData>(rng());  // the ports' values matter only at a start
    }
    rising_edge(*t);
    ++cyc;
  }
  EXPECT_EQ(next, words.size());
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(straight, 1);
}

}  // namespace
}  // namespace tripsitter::rtl
