// The light book-keeping's RTL (ts_path_light.sv) against the model's take_albedo() and sky_light()
// (device/path_kernel.h) with the artix path preset's arithmetic, bit for bit: throughputs from 0 to 1 (65536, the
// white surface's exact 1, among them), albedos of every byte as the device stores them, and escaping directions'
// up components across -1..1 (both ends exactly); each result 2 cycles later with its tag.
#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "path_rtl_util.h"

#include <Vts_path_light.h>

namespace tripsitter::rtl {
namespace {

using Channels = std::array<std::int64_t, 3>;

struct Path {
  Channels throughput{};
  device::PathSurface surface;  // its albedo
  std::int64_t up = 0;
};

struct Light {
  Channels kept{}, light{};
  bool operator==(const Light&) const = default;
};

std::string describe(const Light& l) {
  std::ostringstream s;
  s << "kept " << l.kept[0] << " " << l.kept[1] << " " << l.kept[2] << ", light " << l.light[0] << " " << l.light[1]
    << " " << l.light[2];
  return s.str();
}

Light model(const Path& p) {
  Light out;
  out.light = device::sky_light(device::artix::path_arith(), p.throughput, p.up);
  out.kept = p.throughput;
  device::take_albedo(device::artix::path_arith(), p.surface, out.kept);
  return out;
}

std::vector<Path> random_paths(std::size_t count, std::mt19937_64& rng) {
  std::vector<Path> out;
  for (std::size_t i = 0; i < count; ++i) {
    Path p;
    for (auto& t : p.throughput) t = rng() % 5 == 0 ? 65536 : static_cast<std::int64_t>(rng() % 65537);
    device::SurfaceWord w;
    for (auto& a : w.albedo) a = rng() % 4 == 0 ? 255 : static_cast<std::uint8_t>(rng());
    p.surface = device::path_surface(w);
    const auto pick = rng() % 8;
    p.up = pick == 0 ? 16384 : pick == 1 ? -16384 : static_cast<std::int64_t>(rng() % 32769) - 16384;
    out.push_back(p);
  }
  return out;
}

UInt128 pack3(const Channels& c, int bits) {
  UInt128 v = 0;
  for (int k = 0; k < 3; ++k) v |= static_cast<UInt128>(c[static_cast<std::size_t>(k)]) << (bits * k);
  return v;
}

Channels unpack3(UInt128 v, int bits) {
  Channels c{};
  for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(k)] = static_cast<std::int64_t>((v >> (bits * k)) & static_cast<UInt128>(mask(bits)));
  return c;
}

TEST(PathLightRtl, ThroughputAndSkyAreTheModelsBitForBit) {
  std::mt19937_64 rng(81);
  const std::vector<Path> paths = random_paths(50000, rng);
  VerilatedContext context;
  auto top = path::reset_model<Vts_path_light>(context);
  const int bad = path::stream<Vts_path_light, Path, Light>(
      *top, paths, random_paths(8, rng), 2, rng, [&](std::size_t) { return rng() % 5 != 0; },
      [](Vts_path_light& t, const Path& p) {
        put(t.in_throughput, pack3(p.throughput, 17));
        Channels albedo{};
        for (std::size_t k = 0; k < 3; ++k) albedo[k] = p.surface.albedo[k];
        put(t.in_albedo, pack3(albedo, 17));
        t.in_up = static_cast<IData>(static_cast<std::uint64_t>(p.up) & static_cast<std::uint64_t>(mask(17)));
      },
      [](Vts_path_light& t) { return Light{unpack3(get(t.out_throughput), 17), unpack3(get(t.out_light), 18)}; },
      model);
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace tripsitter::rtl
