// The dielectric bounce's RTL (ts_path_dielectric.sv) against the model's scatter() (device/path_kernel.h) with the
// artix path preset's arithmetic, bit for bit: bounces streamed a cycle each (with gaps and junk between) of random
// directions and normals (meeting the surface from outside and from inside, head on and grazing), on random
// surfaces (indices of refraction across the preset's 0.25 to 8, exactly 1 among them) with random draws; each
// result must come out Latency cycles later with its tag and equal the model's: straight or not, into, refracted,
// whether the draw was taken, and the new direction. The same with the planted bug (the total-internal-reflection
// comparison flipped) must not pass.
#include <cmath>
#include <cstdint>
#include <deque>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include "path_rtl_util.h"

#include <Vts_path_dielectric.h>
#include <Vts_path_dielectric_planted.h>

#include <tripsitter/device/artix_path.h>
#include <tripsitter/device/path_kernel.h>

namespace tripsitter::rtl {
namespace {

using device::approx::Unit3;
using path::random_unit;

constexpr int kLatency = 6 + 16 + 1;  // ts_path_dielectric's

struct Bounce {
  Unit3 in, n;
  bool inside = false;
  device::PathSurface surface;
  std::uint32_t draw = 0;
};

struct Result {
  bool straight = false, into = false, refracted = false, drew = false;
  Unit3 next;
  bool operator==(const Result&) const = default;
};

// The model: scatter() on a dielectric, the draw counted.
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
  r.straight = s.bounce == device::Bounce::kStraight;
  r.into = s.into;
  r.refracted = counters.refracted != 0;
  r.drew = draws != 0;
  if (!r.straight) r.next = s.next;
  return r;
}

std::vector<Bounce> random_bounces(std::size_t count, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Bounce> out;
  for (std::size_t i = 0; i < count; ++i) {
    Bounce b;
    b.n = random_unit(rng);
    b.in = random_unit(rng);
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

template <class Top>
class DielectricRtl {
 public:
  DielectricRtl() {
    context_.randReset(2);
    top_ = std::make_unique<Top>(&context_);
    top_->rst = 1;
    top_->in_valid = 0;
    for (int i = 0; i < 3; ++i) rising_edge(*top_);
    top_->rst = 0;
  }

  // Streams the bounces (a gap one cycle in six, junk on the ports in it); returns how many results differ from
  // the model's. Timing and tags are checked as they come out.
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
      Result got;
      got.straight = top_->out_straight;
      got.into = top_->out_into;
      got.refracted = top_->out_refracted;
      got.drew = top_->out_drew;
      if (!got.straight) {
        got.next = path::unpack(get(top_->out_next));
      }
      if (!(got == s.want)) {
        ++bad;
        if (bad <= 3 && report_) {
          const Bounce& b = bounces[s.tag];
          ADD_FAILURE() << "bounce " << s.tag << " (ior " << b.surface.eta_enter << "/" << b.surface.eta_leave
                        << ", inside " << b.inside << "): rtl straight " << got.straight << " into " << got.into
                        << " refracted " << got.refracted << " drew " << got.drew << " next (" << got.next.x << ", "
                        << got.next.y << ", " << got.next.z << "); model " << s.want.straight << " " << s.want.into
                        << " " << s.want.refracted << " " << s.want.drew << " (" << s.want.next.x << ", "
                        << s.want.next.y << ", " << s.want.next.z << ")";
        }
      }
    }
    EXPECT_EQ(next, bounces.size());
    EXPECT_TRUE(in_flight.empty());
    return bad;
  }
  void set_report(bool report) { report_ = report; }

 private:
  void put_bounce(const Bounce& b, std::uint16_t tag) {
    put(top_->in_dir, path::pack(b.in));
    put(top_->in_normal, path::pack(b.n));
    top_->in_inside = b.inside;
    top_->in_eta_enter = static_cast<IData>(b.surface.eta_enter);
    top_->in_eta_leave = static_cast<IData>(b.surface.eta_leave);
    top_->in_r0 = static_cast<SData>(b.surface.r0);
    top_->in_straight = b.surface.passes_straight;
    top_->in_draw = b.draw;
    top_->in_tag = tag;
  }

  VerilatedContext context_;
  std::unique_ptr<Top> top_;
  bool report_ = true;
};

TEST(PathDielectricRtl, EveryBounceIsTheModelsBitForBit) {
  std::mt19937_64 rng(51);
  const std::vector<Bounce> bounces = random_bounces(30000, rng);
  // The bounces exercise every outcome.
  int straight = 0, tir = 0, reflected = 0, refracted = 0;
  for (const Bounce& b : bounces) {
    const Result r = model(b);
    straight += r.straight;
    tir += !r.straight && !r.drew;
    reflected += !r.straight && r.drew && !r.refracted;
    refracted += r.refracted;
  }
  EXPECT_GT(straight, 500);
  EXPECT_GT(tir, 500);
  EXPECT_GT(reflected, 500);
  EXPECT_GT(refracted, 5000);
  DielectricRtl<Vts_path_dielectric> rtl;
  EXPECT_EQ(rtl.run(bounces, rng), 0);
}

TEST(PathDielectricRtl, APlantedFlippedTotalInternalReflectionTestIsCaught) {
  std::mt19937_64 rng(52);
  const std::vector<Bounce> bounces = random_bounces(3000, rng);
  DielectricRtl<Vts_path_dielectric_planted> planted;
  planted.set_report(false);
  EXPECT_GT(planted.run(bounces, rng), 300) << "the flipped comparison went unnoticed";
}

}  // namespace
}  // namespace tripsitter::rtl
