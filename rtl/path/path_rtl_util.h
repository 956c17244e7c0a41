// What the tests of rtl/path/ share: random unit vectors as the model's 2^14 vectors, the blocks' vector ports
// (three signed fields, x in the low bits), the model's bounce, and the harness that streams a block's inputs and
// checks its results as they come out.
#pragma once

#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"

#include <tripsitter/core/rgb444.h>
#include <tripsitter/device/approx.h>
#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/frame_memory.h>
#include <tripsitter/device/path_kernel.h>

namespace tripsitter::rtl::path {

using device::approx::Unit3;

// A direction uniform on the sphere, each component times 2^14, rounded.
inline Unit3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  const double x = g(rng), y = g(rng), z = g(rng), len = std::sqrt(x * x + y * y + z * z) + 1e-12;
  return {std::llround(x / len * 16384), std::llround(y / len * 16384), std::llround(z / len * 16384)};
}

// v as a port of three `bits`-bit two's complement fields.
inline UInt128 pack(const Unit3& v, int bits = 17) {
  const auto field = [bits](std::int64_t c, int k) {
    return static_cast<UInt128>(static_cast<std::uint64_t>(c) & static_cast<std::uint64_t>(mask(bits))) << (bits * k);
  };
  return field(v.x, 0) | field(v.y, 1) | field(v.z, 2);
}

// A port of three `bits`-bit two's complement fields as a vector.
inline Unit3 unpack(UInt128 port, int bits = 24) {
  return {static_cast<std::int64_t>(sign_extend(port, bits)), static_cast<std::int64_t>(sign_extend(port >> bits, bits)),
          static_cast<std::int64_t>(sign_extend(port >> (2 * bits), bits))};
}

// One bounce of a path at its hit, and what scatter() makes of it.
struct Bounce {
  device::PathSurface surface;
  Unit3 in, n;
  bool inside = false;
  std::uint32_t draw = 0;
};
struct Scatter {
  int bounce = 0;  // device::Bounce: 0 scattered, 1 straight, 2 absorbed
  bool into = false, refracted = false, drew = false;
  Unit3 next;      // a scattered ray's direction (else 0)
  bool operator==(const Scatter&) const = default;
};
static_assert(static_cast<int>(device::Bounce::kScattered) == 0 && static_cast<int>(device::Bounce::kStraight) == 1 &&
              static_cast<int>(device::Bounce::kAbsorbed) == 2);

// The model's bounce with the artix path preset's arithmetic, the draw counted.
inline Scatter model(const Bounce& b) {
  device::PathCounters counters;
  int draws = 0;
  const device::Scattered s = device::scatter(
      device::artix::path_arith(), b.surface, b.n, b.inside, [&] { return b.in; },
      [&] {
        ++draws;
        return b.draw;
      },
      counters);
  Scatter r;
  r.bounce = static_cast<int>(s.bounce);
  r.into = s.into;
  r.refracted = counters.refracted != 0;
  r.drew = draws != 0;
  if (s.bounce == device::Bounce::kScattered) r.next = s.next;
  return r;
}

inline std::string describe(const Scatter& s) {
  return "bounce " + std::to_string(s.bounce) + " into " + std::to_string(s.into) + " refracted " +
         std::to_string(s.refracted) + " drew " + std::to_string(s.drew) + " (" + std::to_string(s.next.x) + ", " +
         std::to_string(s.next.y) + ", " + std::to_string(s.next.z) + ")";
}

inline std::string describe(const core::Rgb444& c) {
  return "colour " + std::to_string(c.r()) + " " + std::to_string(c.g()) + " " + std::to_string(c.b());
}

// A frame-memory entry as the blocks' 64-bit port: {epoch 5, count 8, b, g, r 17 bits each}.
inline std::uint64_t pack(const device::AccumEntry& e) {
  return std::uint64_t{e.sum[0]} | std::uint64_t{e.sum[1]} << 17 | std::uint64_t{e.sum[2]} << 34 |
         std::uint64_t{e.count} << 51 | std::uint64_t{e.epoch} << 59;
}
inline device::AccumEntry unpack_entry(std::uint64_t v) {
  device::AccumEntry e;
  for (std::size_t k = 0; k < 3; ++k) e.sum[k] = static_cast<std::uint32_t>((v >> (17 * k)) & 0x1FFFF);
  e.count = static_cast<std::uint8_t>((v >> 51) & 0xFF);
  e.epoch = static_cast<std::uint8_t>((v >> 59) & 0x1F);
  return e;
}

// A pixel's entry in frame memory for a frame of `epoch`: of that epoch (3 in 4) or another's, and empty, nearly
// full (within `near` of 255 samples: converged for some spp), or anywhere, with sums its count could have.
inline device::AccumEntry random_entry(std::mt19937_64& rng, std::uint8_t epoch, unsigned near) {
  device::AccumEntry e;
  e.epoch = rng() % 4 == 0 ? static_cast<std::uint8_t>(rng() % device::kEpochs) : epoch;
  const auto kind = rng() % 4;
  e.count = kind == 0 ? 0 : kind == 1 ? static_cast<std::uint8_t>(255 - rng() % near) : static_cast<std::uint8_t>(rng() % 256);
  for (auto& s : e.sum) s = static_cast<std::uint32_t>(rng() % (511u * e.count + 1));
  return e;
}

// A Verilated block out of reset: its registers start random (the reset must make them irrelevant), then `rst` is
// high for three clocks with nothing valid going in.
template <class Top>
std::unique_ptr<Top> reset_model(VerilatedContext& context) {
  context.randReset(2);
  auto top = std::make_unique<Top>(&context);
  top->rst = 1;
  top->in_valid = 0;
  for (int i = 0; i < 3; ++i) rising_edge(*top);
  top->rst = 0;
  return top;
}

// A bounce on the ports of the block that takes it (ts_path_dielectric, ts_path_diffuse, ts_path_scatter): the fields
// each has.
template <class Top>
void put_bounce(Top& t, const Bounce& b) {
  put(t.in_dir, pack(b.in));
  put(t.in_normal, pack(b.n));
  t.in_draw = b.draw;
  if constexpr (requires { t.in_material; }) t.in_material = b.surface.material;
  if constexpr (requires { t.in_metal; }) t.in_metal = b.surface.material == link::kMaterialMetal;
  if constexpr (requires { t.in_fuzz; }) t.in_fuzz = b.surface.fuzz;
  if constexpr (requires { t.in_eta_enter; }) {
    t.in_inside = b.inside;
    t.in_eta_enter = static_cast<IData>(b.surface.eta_enter);
    t.in_eta_leave = static_cast<IData>(b.surface.eta_leave);
    t.in_r0 = static_cast<SData>(b.surface.r0);
    t.in_straight = b.surface.passes_straight;
  }
}

// Streams `items` into a Verilated block with a `clk`, `in_valid` and a 16-bit `in_tag` (the item's index), one in each
// cycle send(index) allows, a random junk item's inputs on the ports in the other cycles; checks that each result
// comes out `latency` cycles after its item, once, in order, with its tag; counts the results that differ from the
// model's. put(top, item) sets the item's inputs, got(top) reads a result, want(item) is the model's; at most
// `report` differences are reported. Returns the number that differ.
template <class Top, class Item, class Result>
int stream(Top& top, const std::vector<Item>& items, const std::vector<Item>& junk, int latency, std::mt19937_64& rng,
           const std::function<bool(std::size_t)>& send, const std::function<void(Top&, const Item&)>& put,
           const std::function<Result(Top&)>& got, const std::function<Result(const Item&)>& want, int report = 3) {
  struct Sent {
    std::int64_t cycle;
    Result want;
    std::uint16_t tag;
  };
  std::deque<Sent> in_flight;
  std::size_t next = 0;
  std::int64_t cycle = 0;
  int bad = 0;
  const std::int64_t limit = 10 * static_cast<std::int64_t>(items.size()) + 10 * latency + 100;
  while ((next < items.size() || !in_flight.empty()) && cycle < limit) {
    const bool now = next < items.size() && send(next);
    put(top, now ? items[next] : junk[rng() % junk.size()]);
    top.in_tag = static_cast<SData>(now ? next : rng());
    top.in_valid = now;
    if (now) in_flight.push_back({cycle, want(items[next]), static_cast<std::uint16_t>(next)}), ++next;
    rising_edge(top);
    ++cycle;
    if (!top.out_valid) continue;
    if (in_flight.empty()) {
      ADD_FAILURE() << "a result came out that no item went in for, at cycle " << cycle;
      ++bad;
      continue;
    }
    const Sent s = in_flight.front();
    in_flight.pop_front();
    EXPECT_EQ(cycle - s.cycle, latency) << "item " << s.tag;
    EXPECT_EQ(top.out_tag, s.tag);
    const Result r = got(top);
    if (!(r == s.want) && ++bad <= report)
      ADD_FAILURE() << "item " << s.tag << ": rtl " << describe(r) << "; model " << describe(s.want);
  }
  top.in_valid = 0;
  EXPECT_EQ(next, items.size()) << "the stream did not finish";
  EXPECT_TRUE(in_flight.empty()) << in_flight.size() << " results never came out";
  return bad;
}

}  // namespace tripsitter::rtl::path
