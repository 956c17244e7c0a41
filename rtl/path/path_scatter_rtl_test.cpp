// The scatter unit's RTL (ts_path_scatter.sv) against the model's scatter() (device/path_kernel.h) with the artix
// path preset's arithmetic: bounces off surfaces of every material (random_path_surface: albedos, fuzz, indices as
// the device's tests draw them) streamed back to back and with gaps, materials mixed so that a diffuse bounce and a
// dielectric one follow each other in every order; each result must come out 23 cycles later, in order, with its
// tag, and equal the model's (the bounce, into, refracted, whether the draw was taken, and the direction of a
// scattered ray).
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "path_rtl_util.h"

#include <Vts_path_scatter.h>

#include <tripsitter/device/test_util.h>

namespace tripsitter::rtl {
namespace {

using path::Bounce;
using path::Scatter;

constexpr int kLatency = 23;

std::vector<Bounce> random_bounces(std::size_t count, std::mt19937_64& rng) {
  std::vector<Bounce> out;
  for (std::size_t i = 0; i < count; ++i) {
    Bounce b;
    b.surface = device::path_surface(device::testing::random_path_surface(rng));
    b.n = path::random_unit(rng);
    b.in = path::random_unit(rng);
    b.inside = b.surface.material == link::kMaterialDielectric && rng() % 3 == 0;  // only a dielectric has a far side
    const std::int64_t facing = b.n.x * b.in.x + b.n.y * b.in.y + b.n.z * b.in.z;
    if ((facing > 0) != b.inside) b.in = -b.in;
    b.draw = static_cast<std::uint32_t>(rng());
    out.push_back(b);
  }
  return out;
}

TEST(PathScatterRtl, EveryMaterialsBounceIsTheModelsInOrder) {
  std::mt19937_64 rng(71);
  const std::vector<Bounce> bounces = random_bounces(30000, rng);
  int kinds[3] = {0, 0, 0};
  for (const Bounce& b : bounces) ++kinds[b.surface.material];
  EXPECT_GT(kinds[0], 5000);
  EXPECT_GT(kinds[1], 5000);
  EXPECT_GT(kinds[2], 5000);
  VerilatedContext context;
  auto top = path::reset_model<Vts_path_scatter>(context);
  const int bad = path::stream<Vts_path_scatter, Bounce, Scatter>(
      *top, bounces, random_bounces(8, rng), kLatency, rng,
      [&](std::size_t i) { return i < 10000 || rng() % 4 != 0; },  // back to back, then with gaps
      path::put_bounce<Vts_path_scatter>,
      [](Vts_path_scatter& t) {
        Scatter s;
        s.bounce = t.out_bounce;
        s.into = t.out_into;
        s.refracted = t.out_refracted;
        s.drew = t.out_drew;
        if (s.bounce == 0) s.next = path::unpack(get(t.out_next));
        return s;
      },
      path::model);
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace tripsitter::rtl
