// The lambertian and metal bounces' RTL (ts_path_diffuse.sv) against the model's scatter() (device/path_kernel.h)
// with the artix path preset's arithmetic, bit for bit: bounces streamed a cycle each (gaps and junk between) of
// random directions and normals, both materials, fuzz 0, 1 (65535 / 65536) and between, and random draws (every
// azimuth of the sine table among them); each result must come out Latency cycles later with its tag and equal the
// model's: the new direction, absorbed or not, and whether the draw was taken.
#include <cmath>
#include <cstdint>
#include <deque>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "path_rtl_util.h"

#include <Vts_path_diffuse.h>

#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/path_kernel.h>

namespace tripsitter::rtl {
namespace {

using device::approx::Unit3;
using path::random_unit;

constexpr int kLatency = 20;  // ts_path_diffuse's

struct Bounce {
  bool metal = false;
  Unit3 in, n;
  std::uint16_t fuzz = 0;
  std::uint32_t draw = 0;
};

struct Result {
  bool absorbed = false, drew = false;
  Unit3 next;
  bool operator==(const Result&) const = default;
};

Result model(const Bounce& b) {
  device::PathSurface surface;
  surface.material = b.metal ? link::kMaterialMetal : link::kMaterialLambertian;
  surface.fuzz = b.fuzz;
  device::PathCounters counters;
  int draws = 0;
  const device::Scattered s = device::scatter(
      device::artix::path_arith(), surface, b.n, false, [&] { return b.in; },
      [&] {
        ++draws;
        return b.draw;
      },
      counters);
  return {s.bounce == device::Bounce::kAbsorbed, draws != 0, s.next};
}

// The edges random draws rarely reach: a mirror exactly along the surface (next.n = 0: absorbed, as <= 0 says),
// and lambertian draws of z = -1 against a normal straight up, where n + u is shorter than 2^-6 and the normal is kept.
std::vector<Bounce> edge_bounces() {
  std::vector<Bounce> out;
  const Unit3 x{16384, 0, 0}, y{0, 16384, 0}, z{0, 0, 16384};
  for (const auto& [in, n] : {std::pair{y, x}, std::pair{x, z}, std::pair{-z, y}})
    out.push_back({true, in, n, 0, 12345});
  for (std::uint32_t phi = 0; phi < 4096; phi += 512) out.push_back({false, -z, z, 0, phi << 5});
  return out;
}

std::vector<Bounce> random_bounces(std::size_t count, std::mt19937_64& rng) {
  std::vector<Bounce> out;
  for (std::size_t i = 0; i < count; ++i) {
    Bounce b;
    b.metal = rng() % 2 == 0;
    b.n = random_unit(rng);
    b.in = random_unit(rng);
    const std::int64_t facing = b.n.x * b.in.x + b.n.y * b.in.y + b.n.z * b.in.z;
    if (facing > 0 && rng() % 8 != 0) b.in = -b.in;  // mostly meeting the surface from outside
    const auto pick = rng() % 4;
    b.fuzz = pick == 0 ? 0 : pick == 1 ? 65535 : static_cast<std::uint16_t>(rng());
    b.draw = static_cast<std::uint32_t>(rng());
    if (i < 4096) b.draw = (b.draw & ~(4095u << 5)) | (static_cast<std::uint32_t>(i) << 5);  // every azimuth
    out.push_back(b);
  }
  return out;
}

class DiffuseRtl {
 public:
  DiffuseRtl() {
    context_.randReset(2);
    top_ = std::make_unique<Vts_path_diffuse>(&context_);
    top_->rst = 1;
    top_->in_valid = 0;
    for (int i = 0; i < 3; ++i) rising_edge(*top_);
    top_->rst = 0;
  }

  int run(const std::vector<Bounce>& bounces, std::mt19937_64& rng) {
    struct Sent {
      std::int64_t cycle;
      Result want;
      std::uint16_t tag;
    };
    std::deque<Sent> in_flight;
    std::size_t next = 0;
    std::int64_t cycle = 0;
    int bad = 0;
    const std::vector<Bounce> junk = random_bounces(8, rng);
    while ((next < bounces.size() || !in_flight.empty()) && cycle < 10 * static_cast<std::int64_t>(bounces.size()) + 100) {
      const bool send = next < bounces.size() && rng() % 6 != 0;
      const Bounce& b = send ? bounces[next] : junk[rng() % junk.size()];
      put_bounce(b, static_cast<std::uint16_t>(send ? next : rng()));
      top_->in_valid = send;
      if (send) in_flight.push_back({cycle, model(b), static_cast<std::uint16_t>(next++)});
      rising_edge(*top_);
      ++cycle;
      if (!top_->out_valid) continue;
      if (in_flight.empty()) {
        ADD_FAILURE() << "a result came out that no bounce went in for";
        ++bad;
        continue;
      }
      const Sent s = in_flight.front();
      in_flight.pop_front();
      EXPECT_EQ(cycle - s.cycle, kLatency);
      EXPECT_EQ(top_->out_tag, s.tag);
      const Result got{top_->out_absorbed != 0, top_->out_drew != 0, path::unpack(get(top_->out_next))};
      if (!(got == s.want) && ++bad <= 3) {
        const Bounce& b = bounces[s.tag];
        ADD_FAILURE() << "bounce " << s.tag << (b.metal ? " metal" : " lambertian") << " fuzz " << b.fuzz << " draw "
                      << b.draw << ": rtl absorbed " << got.absorbed << " drew " << got.drew << " next (" << got.next.x
                      << ", " << got.next.y << ", " << got.next.z << "); model " << s.want.absorbed << " "
                      << s.want.drew << " (" << s.want.next.x << ", " << s.want.next.y << ", " << s.want.next.z << ")";
      }
    }
    EXPECT_EQ(next, bounces.size());
    EXPECT_TRUE(in_flight.empty());
    return bad;
  }

 private:
  void put_bounce(const Bounce& b, std::uint16_t tag) {
    top_->in_metal = b.metal;
    put(top_->in_dir, path::pack(b.in));
    put(top_->in_normal, path::pack(b.n));
    top_->in_fuzz = b.fuzz;
    top_->in_draw = b.draw;
    top_->in_tag = tag;
  }

  VerilatedContext context_;
  std::unique_ptr<Vts_path_diffuse> top_;
};

TEST(PathDiffuseRtl, EveryBounceIsTheModelsBitForBit) {
  std::mt19937_64 rng(61);
  std::vector<Bounce> bounces = edge_bounces();
  const std::vector<Bounce> random = random_bounces(30000, rng);
  bounces.insert(bounces.end(), random.begin(), random.end());
  int absorbed = 0, metal_draws = 0, short_lambertian = 0;
  for (const Bounce& b : bounces) {
    const Result r = model(b);
    absorbed += r.absorbed;
    metal_draws += b.metal && r.drew;
    short_lambertian += !b.metal && r.next == b.n;
  }
  EXPECT_GT(absorbed, 100);
  EXPECT_GT(metal_draws, 5000);
  EXPECT_GE(short_lambertian, 8);
  std::printf("absorbed %d, metals that drew %d, lambertian bounces that kept the normal %d\n", absorbed, metal_draws,
              short_lambertian);
  DiffuseRtl rtl;
  EXPECT_EQ(rtl.run(bounces, rng), 0);
}

}  // namespace
}  // namespace tripsitter::rtl
