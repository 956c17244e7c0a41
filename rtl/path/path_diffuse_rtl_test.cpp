// The lambertian and metal bounces' RTL (ts_path_diffuse.sv) against the model's scatter() (device/path_kernel.h)
// with the artix path preset's arithmetic, bit for bit: bounces streamed a cycle each (gaps and junk between) of
// random directions and normals, both materials, fuzz 0, 1 (65535 / 65536) and between, and random draws (every
// azimuth of the sine table among them); each result must come out Latency cycles later with its tag and equal the
// model's: the new direction, absorbed or not, and whether the draw was taken.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "path_rtl_util.h"

#include <Vts_path_diffuse.h>

namespace tripsitter::rtl {
namespace {

using device::approx::Unit3;
using path::Bounce;
using path::Scatter;

constexpr int kLatency = 20;  // ts_path_diffuse's

Bounce bounce_of(bool metal, const Unit3& in, const Unit3& n, std::uint16_t fuzz, std::uint32_t draw) {
  Bounce b;
  b.surface.material = metal ? link::kMaterialMetal : link::kMaterialLambertian;
  b.surface.fuzz = fuzz;
  b.in = in;
  b.n = n;
  b.draw = draw;
  return b;
}

// The edges random draws rarely reach: a mirror exactly along the surface (next.n = 0: absorbed, as <= 0 says),
// and lambertian draws of z = -1 against a normal straight up, where n + u is shorter than 2^-6 and the normal is kept.
std::vector<Bounce> edge_bounces() {
  std::vector<Bounce> out;
  const Unit3 x{16384, 0, 0}, y{0, 16384, 0}, z{0, 0, 16384};
  for (const auto& [in, n] : {std::pair{y, x}, std::pair{x, z}, std::pair{-z, y}})
    out.push_back(bounce_of(true, in, n, 0, 12345));
  for (std::uint32_t phi = 0; phi < 4096; phi += 512) out.push_back(bounce_of(false, -z, z, 0, phi << 5));
  return out;
}

std::vector<Bounce> random_bounces(std::size_t count, std::mt19937_64& rng) {
  std::vector<Bounce> out;
  for (std::size_t i = 0; i < count; ++i) {
    const bool metal = rng() % 2 == 0;
    const Unit3 n = path::random_unit(rng);
    Unit3 in = path::random_unit(rng);
    const std::int64_t facing = n.x * in.x + n.y * in.y + n.z * in.z;
    if (facing > 0 && rng() % 8 != 0) in = -in;  // mostly meeting the surface from outside
    const auto pick = rng() % 4;
    const std::uint16_t fuzz = pick == 0 ? 0 : pick == 1 ? 65535 : static_cast<std::uint16_t>(rng());
    auto draw = static_cast<std::uint32_t>(rng());
    if (i < 4096) draw = (draw & ~(4095u << 5)) | (static_cast<std::uint32_t>(i) << 5);  // every azimuth
    out.push_back(bounce_of(metal, in, n, fuzz, draw));
  }
  return out;
}

TEST(PathDiffuseRtl, EveryBounceIsTheModelsBitForBit) {
  std::mt19937_64 rng(61);
  std::vector<Bounce> bounces = edge_bounces();
  const std::vector<Bounce> random = random_bounces(30000, rng);
  bounces.insert(bounces.end(), random.begin(), random.end());
  int absorbed = 0, metal_draws = 0, short_lambertian = 0;
  for (const Bounce& b : bounces) {
    const Scatter r = path::model(b);
    const bool metal = b.surface.material == link::kMaterialMetal;
    absorbed += r.bounce == 2;
    metal_draws += metal && r.drew;
    short_lambertian += !metal && r.next == b.n;
  }
  EXPECT_GT(absorbed, 100);
  EXPECT_GT(metal_draws, 5000);
  EXPECT_GE(short_lambertian, 8);
  std::printf("absorbed %d, metals that drew %d, lambertian bounces that kept the normal %d\n", absorbed, metal_draws,
              short_lambertian);
  VerilatedContext context;
  auto top = path::reset_model<Vts_path_diffuse>(context);
  const int bad = path::stream<Vts_path_diffuse, Bounce, Scatter>(
      *top, bounces, random_bounces(8, rng), kLatency, rng, [&](std::size_t) { return rng() % 6 != 0; },
      path::put_bounce<Vts_path_diffuse>,
      [](Vts_path_diffuse& t) {
        Scatter s;
        s.bounce = t.out_absorbed ? 2 : 0;
        s.drew = t.out_drew;
        if (s.bounce == 0) s.next = path::unpack(get(t.out_next));
        return s;
      },
      path::model);
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace tripsitter::rtl
