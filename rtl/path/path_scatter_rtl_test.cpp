// The scatter unit's RTL (ts_path_scatter.sv) against the model's scatter() (device/path_kernel.h) with the artix
// path preset's arithmetic: bounces off surfaces of every material (random_path_surface: albedos, fuzz, indices as
// the device's tests draw them) streamed back to back and with gaps, materials mixed so that a diffuse bounce and a
// dielectric one follow each other in every order; each result must come out 23 cycles later, in order, with its
// tag, and equal the model's (the bounce, into, refracted, whether the draw was taken, and the direction of a
// scattered ray).
#include <cstdint>
#include <deque>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "path_rtl_util.h"

#include <Vts_path_scatter.h>

#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/path_kernel.h>
#include <tripsitter/device/test_util.h>

namespace tripsitter::rtl {
namespace {

using device::approx::Unit3;

constexpr int kLatency = 23;

struct Bounce {
  device::PathSurface surface;
  Unit3 in, n;
  bool inside = false;
  std::uint32_t draw = 0;
};

struct Result {
  int bounce = 0;  // device::Bounce's order: scattered, straight, absorbed
  bool into = false, refracted = false, drew = false;
  Unit3 next;
  bool operator==(const Result&) const = default;
};

Result model(const Bounce& b) {
  device::PathCounters counters;
  int draws = 0;
  const device::Scattered s = device::scatter(
      device::artix::path_arith(), b.surface, b.n, b.inside, [&] { return b.in; },
      [&] {
        ++draws;
        return b.draw;
      },
      counters);
  Result r;
  r.bounce = s.bounce == device::Bounce::kScattered ? 0 : s.bounce == device::Bounce::kStraight ? 1 : 2;
  r.into = s.into;
  r.refracted = counters.refracted != 0;
  r.drew = draws != 0;
  if (r.bounce == 0) r.next = s.next;
  return r;
}

TEST(PathScatterRtl, EveryMaterialsBounceIsTheModelsInOrder) {
  static_assert(static_cast<int>(device::Bounce::kScattered) == 0 && static_cast<int>(device::Bounce::kStraight) == 1 &&
                static_cast<int>(device::Bounce::kAbsorbed) == 2);
  std::mt19937_64 rng(71);
  std::vector<Bounce> bounces;
  int kinds[3] = {0, 0, 0};
  for (int i = 0; i < 30000; ++i) {
    Bounce b;
    b.surface = device::path_surface(device::testing::random_path_surface(rng));
    b.n = path::random_unit(rng);
    b.in = path::random_unit(rng);
    const bool dielectric = b.surface.material == link::kMaterialDielectric;
    b.inside = dielectric && rng() % 3 == 0;  // only a dielectric has a far side to hit from inside
    const std::int64_t facing = b.n.x * b.in.x + b.n.y * b.in.y + b.n.z * b.in.z;
    if ((facing > 0) != b.inside) b.in = -b.in;
    b.draw = static_cast<std::uint32_t>(rng());
    ++kinds[b.surface.material];
    bounces.push_back(b);
  }
  EXPECT_GT(kinds[0], 5000);
  EXPECT_GT(kinds[1], 5000);
  EXPECT_GT(kinds[2], 5000);

  VerilatedContext context;
  context.randReset(2);
  auto top = std::make_unique<Vts_path_scatter>(&context);
  top->rst = 1;
  top->in_valid = 0;
  for (int i = 0; i < 3; ++i) rising_edge(*top);
  top->rst = 0;
  struct Sent {
    std::int64_t cycle;
    Result want;
    std::uint16_t tag;
  };
  std::deque<Sent> in_flight;
  std::size_t next = 0;
  std::int64_t cycle = 0;
  int bad = 0;
  while ((next < bounces.size() || !in_flight.empty()) && cycle < 200000) {
    const bool send = next < bounces.size() && (next < 10000 || rng() % 4 != 0);  // back to back, then with gaps
    const Bounce& b = bounces[send ? next : rng() % bounces.size()];
    top->in_material = b.surface.material;
    put(top->in_dir, path::pack(b.in));
    put(top->in_normal, path::pack(b.n));
    top->in_inside = b.inside;
    top->in_fuzz = b.surface.fuzz;
    top->in_eta_enter = static_cast<IData>(b.surface.eta_enter);
    top->in_eta_leave = static_cast<IData>(b.surface.eta_leave);
    top->in_r0 = static_cast<SData>(b.surface.r0);
    top->in_straight = b.surface.passes_straight;
    top->in_draw = b.draw;
    top->in_tag = static_cast<SData>(send ? next : rng());
    top->in_valid = send;
    if (send) in_flight.push_back({cycle, model(b), static_cast<std::uint16_t>(next++)});
    rising_edge(*top);
    ++cycle;
    if (!top->out_valid) continue;
    ASSERT_FALSE(in_flight.empty()) << "a result came out that no bounce went in for";
    const Sent s = in_flight.front();
    in_flight.pop_front();
    ASSERT_EQ(cycle - s.cycle, kLatency);
    ASSERT_EQ(top->out_tag, s.tag);
    Result got;
    got.bounce = top->out_bounce;
    got.into = top->out_into;
    got.refracted = top->out_refracted;
    got.drew = top->out_drew;
    if (got.bounce == 0) got.next = path::unpack(get(top->out_next));
    if (!(got == s.want) && ++bad <= 3) {
      ADD_FAILURE() << "bounce " << s.tag << " (material " << int{bounces[s.tag].surface.material} << "): rtl "
                    << got.bounce << " " << got.into << " " << got.refracted << " " << got.drew << " (" << got.next.x
                    << ", " << got.next.y << ", " << got.next.z << "); model " << s.want.bounce << " " << s.want.into
                    << " " << s.want.refracted << " " << s.want.drew << " (" << s.want.next.x << ", " << s.want.next.y
                    << ", " << s.want.next.z << ")";
    }
  }
  EXPECT_EQ(next, bounces.size());
  EXPECT_TRUE(in_flight.empty());
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace tripsitter::rtl
