// The artix per-world constants' RTL (ts_artix_prepare.sv) against artix::prepare_sphere, bit for bit, for every
// radius the formats allow (1 .. 2^21 - 1), back to back; and its handshake to the cycle: done exactly Cycles after
// each start, ready low in between and high again in the done cycle, a start while busy ignored, a reset dropping
// the sphere in work.
#include <cstdint>
#include <memory>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_artix_prepare.h>

#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/artix_kernel.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;

constexpr int kCycles = 24;       // ts_artix_prepare's Cycles: from a start to its done and to ready again
constexpr int kExpW = 6;          // ts_artix_pkg::ExpW
constexpr std::int64_t kRadii = std::int64_t{1} << artix::kMaxRadiusBits;  // radii are below 2^21

struct Constants {
  std::int64_t e = 0;
  std::int64_t r2s = 0;
  std::int64_t rinv = 0;
  bool operator==(const Constants&) const = default;
};

Constants model(std::int64_t r) {
  core::KernelSphere<std::int64_t> sphere;
  sphere.radius = r;
  const artix::UnitSphere u = artix::prepare_sphere(sphere, core::KernelSurface{});
  return {u.e, u.r2s, u.rinv};
}

// One Verilated block, clocked by hand: inputs are set, then the rising edge moves everything on by a cycle.
class PrepareRtl {
 public:
  PrepareRtl() {
    context_.randReset(2);  // random initial values: the reset must make them irrelevant
    top_ = std::make_unique<Vts_artix_prepare>(&context_);
    top_->rst = 1;
    top_->start = 0;
    for (int i = 0; i < 3; ++i) tick();
    top_->rst = 0;
  }

  // Starts r in this cycle and returns its constants from the done cycle, checking the handshake on the way: ready
  // at the start, then no done and no ready until exactly kCycles later, then both. `start` stays high with another
  // radius in the busy cycles, which the block must ignore. Ends in the done cycle, where the next start may come.
  Constants prepare(std::int64_t r) {
    if (!top_->ready) fault(r, "not ready for the start");
    top_->start = 1;
    top_->in_r = static_cast<IData>(r);
    tick();
    top_->in_r = static_cast<IData>(r ^ 0x0aaaaa);  // a start without ready
    for (int k = 1; k < kCycles; ++k) {
      if (top_->done || top_->ready) {
        fault(r, "done or ready " + std::to_string(k) + " cycles after the start");
        break;
      }
      tick();
    }
    if (!top_->done) fault(r, "no done " + std::to_string(kCycles) + " cycles after the start");
    if (!top_->ready) fault(r, "not ready in the done cycle");
    top_->start = 0;
    return {static_cast<std::int64_t>(sign_extend(top_->out_e, kExpW)), static_cast<std::int64_t>(top_->out_r2s),
            static_cast<std::int64_t>(top_->out_rinv)};
  }

  // Handshake faults so far (the first few reported).
  int faults() const { return faults_; }

  // Cycles with start low: done must not come, ready must stay.
  void idle(int cycles) {
    top_->start = 0;
    for (int i = 0; i < cycles; ++i) {
      tick();
      EXPECT_EQ(top_->done, 0) << "a done with no start";
      EXPECT_EQ(top_->ready, 1) << "not ready while idle";
    }
  }

  // Starts r, resets the block `after` cycles later, and checks that it is ready at once and never gives a done.
  void reset_after(std::int64_t r, int after) {
    top_->start = 1;
    top_->in_r = static_cast<IData>(r);
    tick();
    top_->start = 0;
    for (int k = 1; k < after; ++k) tick();
    top_->rst = 1;
    tick();
    top_->rst = 0;
    EXPECT_EQ(top_->ready, 1) << "not ready after a reset";
    idle(2 * kCycles);
  }

 private:
  void tick() {
    rising_edge(*top_);
  }

  void fault(std::int64_t r, const std::string& what) {
    if (faults_++ < 5) ADD_FAILURE() << "radius " << r << ": " << what;
  }

  VerilatedContext context_;
  std::unique_ptr<Vts_artix_prepare> top_;
  int faults_ = 0;
};

// Whether the RTL's constants for r are the model's; the first few mismatches are reported.
bool agrees(PrepareRtl& rtl, std::int64_t r, int& mismatches) {
  const Constants got = rtl.prepare(r);
  const Constants expected = model(r);
  if (got == expected) return true;
  if (mismatches++ < 5) {
    ADD_FAILURE() << "radius " << r << ": (e, r2s, rinv) = (" << got.e << ", " << got.r2s << ", " << got.rinv
                  << ") in the RTL, (" << expected.e << ", " << expected.r2s << ", " << expected.rinv
                  << ") in the model";
  }
  return false;
}

TEST(ArtixPrepareRtl, EveryRadiusEqualsTheModel) {
  PrepareRtl rtl;
  int mismatches = 0;
  for (std::int64_t r = 1; r < kRadii && mismatches + rtl.faults() < 5; ++r) agrees(rtl, r, mismatches);
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(rtl.faults(), 0);
  rtl.idle(3);
}

TEST(ArtixPrepareRtl, HandshakeAfterGapsAndResets) {
  PrepareRtl rtl;
  int mismatches = 0;
  rtl.idle(5);
  std::mt19937 rng(11);
  for (int i = 0; i < 200; ++i) {
    const std::int64_t r = 1 + static_cast<std::int64_t>(rng() % (kRadii - 1));
    agrees(rtl, r, mismatches);
    rtl.idle(static_cast<int>(rng() % 4));
    if (i % 50 == 49) {
      rtl.reset_after(r, 1 + i % (kCycles - 1));
    }
  }
  // The extremes, each after a reset in its neighbour's work.
  for (const std::int64_t r : {std::int64_t{1}, kRadii - 1, std::int64_t{1} << 16, (std::int64_t{1} << 17) - 1}) {
    rtl.reset_after(kRadii - r, kCycles - 1);
    agrees(rtl, r, mismatches);
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(rtl.faults(), 0);
}

}  // namespace
}  // namespace tripsitter::rtl
