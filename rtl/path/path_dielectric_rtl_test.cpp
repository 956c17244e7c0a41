// The dielectric bounce's RTL (ts_path_dielectric.sv) against the model's scatter() (device/path_kernel.h) with the
// artix path preset's arithmetic, bit for bit: bounces streamed a cycle each (with gaps and junk between) of random
// directions and normals (meeting the surface from outside and from inside, head on and grazing), on random
// surfaces (indices of refraction across the preset's 0.25 to 8, exactly 1 among them) with random draws; each
// result must come out Latency cycles later with its tag and equal the model's: straight or not, into, refracted,
// whether the draw was taken, and the new direction. The same with the planted bug (the total-internal-reflection
// comparison flipped) must not pass.
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "path_rtl_util.h"

#include <Vts_path_dielectric.h>
#include <Vts_path_dielectric_planted.h>

namespace tripsitter::rtl {
namespace {

using path::Bounce;
using path::Scatter;

constexpr int kLatency = 6 + 16 + 1;  // ts_path_dielectric's

std::vector<Bounce> random_bounces(std::size_t count, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Bounce> out;
  for (std::size_t i = 0; i < count; ++i) {
    Bounce b;
    b.n = path::random_unit(rng);
    b.in = path::random_unit(rng);
    b.inside = rng() % 2 == 0;
    // Facing as a ray meets the surface: against the normal from outside, along it from inside; now and then
    // grazing (a direction across the normal), and now and then anything.
    const std::int64_t facing = b.n.x * b.in.x + b.n.y * b.in.y + b.n.z * b.in.z;
    if (rng() % 8 != 0 && ((facing > 0) != b.inside)) b.in = -b.in;
    if (rng() % 10 == 0) {  // grazing: in minus its part along n, renormalised
      const double f = static_cast<double>(facing) / (16384.0 * 16384.0);
      const double x = b.in.x - f * b.n.x, y = b.in.y - f * b.n.y, z = b.in.z - f * b.n.z;
      const double len = std::sqrt(x * x + y * y + z * z) + 1e-9;
      b.in = {std::llround(x / len * 16384), std::llround(y / len * 16384), std::llround(z / len * 16384)};
    }
    device::SurfaceWord w;
    w.material = link::kMaterialDielectric;
    const double pick = unit(rng);
    w.ior = pick < 0.05   ? std::uint16_t{4096}  // exactly 1: straight through
            : pick < 0.1  ? device::kPathIorMin
            : pick < 0.15 ? device::kPathIorMax
            : pick < 0.6  ? static_cast<std::uint16_t>(4096 * (1.2 + 0.8 * unit(rng)))
                          : static_cast<std::uint16_t>(device::kPathIorMin +
                                                       rng() % (device::kPathIorMax - device::kPathIorMin + 1));
    b.surface = device::path_surface(w);
    b.draw = static_cast<std::uint32_t>(rng());
    out.push_back(b);
  }
  return out;
}

// Streams the bounces (a gap one cycle in six) through a Verilated dielectric; returns how many results differ.
template <class Top>
int run(const std::vector<Bounce>& bounces, std::mt19937_64& rng, int report) {
  VerilatedContext context;
  auto top = path::reset_model<Top>(context);
  return path::stream<Top, Bounce, Scatter>(
      *top, bounces, random_bounces(8, rng), kLatency, rng, [&](std::size_t) { return rng() % 6 != 0; },
      path::put_bounce<Top>,
      [](Top& t) {
        Scatter s;
        s.bounce = t.out_straight ? 1 : 0;
        s.into = t.out_into;
        s.refracted = t.out_refracted;
        s.drew = t.out_drew;
        if (s.bounce == 0) s.next = path::unpack(get(t.out_next));
        return s;
      },
      path::model, report);
}

TEST(PathDielectricRtl, EveryBounceIsTheModelsBitForBit) {
  std::mt19937_64 rng(51);
  const std::vector<Bounce> bounces = random_bounces(30000, rng);
  // The bounces exercise every outcome.
  int straight = 0, tir = 0, reflected = 0, refracted = 0;
  for (const Bounce& b : bounces) {
    const Scatter r = path::model(b);
    straight += r.bounce == 1;
    tir += r.bounce == 0 && !r.drew;
    reflected += r.bounce == 0 && r.drew && !r.refracted;
    refracted += r.refracted;
  }
  EXPECT_GT(straight, 500);
  EXPECT_GT(tir, 500);
  EXPECT_GT(reflected, 500);
  EXPECT_GT(refracted, 5000);
  EXPECT_EQ(run<Vts_path_dielectric>(bounces, rng, 3), 0);
}

TEST(PathDielectricRtl, APlantedFlippedTotalInternalReflectionTestIsCaught) {
  std::mt19937_64 rng(52);
  const std::vector<Bounce> bounces = random_bounces(3000, rng);
  EXPECT_GT(run<Vts_path_dielectric_planted>(bounces, rng, 0), 300) << "the flipped comparison went unnoticed";
}

}  // namespace
}  // namespace tripsitter::rtl
