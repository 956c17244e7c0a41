// The artix camera's RTL (ts_artix_camera.sv) against artix::camera_direction, bit for bit: every pixel of the
// screen streamed back to back, random pixels with a pattern of gaps (and junk on the ports between them), and a
// reset that drops the pixels in flight. Each direction must come out exactly Latency cycles after its pixel went
// in, once, in order, with its tag.
#include <cstdint>
#include <deque>
#include <memory>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_artix_camera.h>

#include <tripsitter/core/screen.h>
#include <tripsitter/device/artix_kernel.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;

constexpr int kLatency = 11;  // ts_artix_camera's Latency
constexpr int kDirW = 18;     // ts_artix_pkg::DirW
constexpr int kColBits = 10;  // the tag is {row, col}: TAG_W = 19 in the build

struct Pixel {
  int col = 0;
  int row = 0;
};

// One Verilated camera, clocked by hand: inputs are set, the model settles with the clock low, and the rising edge
// moves everything on by a cycle.
class CameraRtl {
 public:
  CameraRtl() {
    context_.randReset(2);  // random initial values: the reset must make them irrelevant
    top_ = std::make_unique<Vts_artix_camera>(&context_);
    top_->rst = 1;
    top_->in_valid = 0;
    for (int i = 0; i < 3; ++i) tick();
    top_->rst = 0;
  }

  // Streams `pixels`, one in each cycle where `gap` says no gap (and junk on the ports in the gaps), and checks
  // every direction as it comes out. Returns the number of directions that differ from the model's.
  template <class Gap>
  int run(const std::vector<Pixel>& pixels, const Gap& gap, std::mt19937& junk) {
    std::size_t next = 0;
    int bad = 0;
    const std::int64_t limit = cycle_ + 4 * static_cast<std::int64_t>(pixels.size()) + 4 * kLatency;
    while ((next < pixels.size() || !in_flight_.empty()) && cycle_ < limit) {
      const bool send = next < pixels.size() && !gap(cycle_);
      const Pixel p = send ? pixels[next++] : Pixel{static_cast<int>(junk() % 1024), static_cast<int>(junk() % 512)};
      top_->in_valid = send;
      top_->in_col = static_cast<SData>(p.col);
      top_->in_row = static_cast<SData>(p.row);
      top_->in_tag = static_cast<IData>(p.row << kColBits | p.col);
      if (send) in_flight_.push_back({cycle_, p});
      tick();
      bad += check_output();
    }
    top_->in_valid = 0;
    EXPECT_EQ(next, pixels.size()) << "the stream did not finish";
    EXPECT_TRUE(in_flight_.empty()) << in_flight_.size() << " directions never came out";
    return bad;
  }

  // Sends `pixels`, then resets the camera `after` cycles later, before the first could come out: none of them may
  // come out, before the reset or after.
  void reset_after(const std::vector<Pixel>& pixels, int after) {
    ASSERT_LT(static_cast<int>(pixels.size()) + after, kLatency);
    for (const Pixel& p : pixels) {
      top_->in_valid = 1;
      top_->in_col = static_cast<SData>(p.col);
      top_->in_row = static_cast<SData>(p.row);
      tick();
      EXPECT_EQ(top_->out_valid, 0) << "a direction came out early";
    }
    top_->in_valid = 0;
    for (int i = 0; i < after; ++i) {
      tick();
      EXPECT_EQ(top_->out_valid, 0) << "a direction came out early";
    }
    top_->rst = 1;
    tick();
    top_->rst = 0;
    for (int i = 0; i < 2 * kLatency; ++i) {
      tick();
      EXPECT_EQ(top_->out_valid, 0) << "a direction in flight at the reset came out";
    }
  }

 private:
  struct Sent {
    std::int64_t cycle;
    Pixel pixel;
  };

  void tick() {
    rising_edge(*top_);
    ++cycle_;
  }

  // The output after the edge that ended cycle cycle_ - 1: what the ports hold in cycle cycle_.
  int check_output() {
    if (!top_->out_valid) return 0;
    if (in_flight_.empty()) {
      ADD_FAILURE() << "a direction with no pixel, in cycle " << cycle_;
      return 1;
    }
    const Sent sent = in_flight_.front();
    in_flight_.pop_front();
    const Pixel p = sent.pixel;
    EXPECT_EQ(cycle_ - sent.cycle, kLatency) << "latency of pixel (" << p.col << ", " << p.row << ")";
    EXPECT_EQ(top_->out_tag, static_cast<IData>(p.row << kColBits | p.col)) << "directions out of order";
    const artix::Vec3i expected = artix::camera_direction(p.col, p.row);
    const UInt128 d = get(top_->out_d);
    for (int k = 0; k < 3; ++k) {
      const auto got = static_cast<std::int64_t>(sign_extend(d >> (kDirW * k), kDirW));
      if (got != expected[static_cast<std::size_t>(k)]) {
        ADD_FAILURE() << "pixel (" << p.col << ", " << p.row << "): d[" << k << "] is " << got << " in the RTL, "
                      << expected[static_cast<std::size_t>(k)] << " in the model";
        return 1;
      }
    }
    return 0;
  }

  VerilatedContext context_;
  std::unique_ptr<Vts_artix_camera> top_;
  std::int64_t cycle_ = 0;
  std::deque<Sent> in_flight_;
};

std::vector<Pixel> every_pixel() {
  std::vector<Pixel> v;
  for (int row = 0; row < core::kScreenHeight; ++row)
    for (int col = 0; col < core::kScreenWidth; ++col) v.push_back({col, row});
  return v;
}

// n >> 9 of the pixel: the seed it takes.
int seed_of(const Pixel& p) {
  const int x = p.col - 320;
  const int y = p.row - 240;
  return (x * x + y * y + 320 * 320) >> 9;
}

TEST(ArtixCameraRtl, EveryPixelBackToBackEqualsTheModel) {
  const std::vector<Pixel> pixels = every_pixel();
  // The screen takes every entry of the seed table, so this checks the whole table.
  std::set<int> seeds;
  for (const Pixel& p : pixels) seeds.insert(seed_of(p));
  ASSERT_EQ(seeds.size(), static_cast<std::size_t>(artix::kSeedEntries));
  ASSERT_EQ(*seeds.begin(), artix::kSeedFirst);
  ASSERT_EQ(*seeds.rbegin(), artix::kSeedLast);
  // ... and the one saturated component: the centre's z, 320 g rounded to 2^17.
  ASSERT_EQ(artix::camera_direction(320, 240)[2], artix::kDirectionMax);

  CameraRtl rtl;
  std::mt19937 junk(1);
  EXPECT_EQ(rtl.run(pixels, [](std::int64_t) { return false; }, junk), 0);
}

TEST(ArtixCameraRtl, RandomPixelsWithGapsEqualTheModel) {
  std::mt19937 rng(20240611);
  std::vector<Pixel> pixels(60000);
  for (Pixel& p : pixels) {
    p.col = static_cast<int>(rng() % core::kScreenWidth);
    p.row = static_cast<int>(rng() % core::kScreenHeight);
  }
  // Single gaps, runs of gaps longer than the pipeline, and stretches without any: a gap with probability 1/3 in
  // cycles whose 64-cycle block is odd, none in even blocks, and every 16th block a run of 20 gaps.
  std::mt19937 pattern(7);
  std::mt19937 junk(3);
  const auto gap = [&pattern](std::int64_t cycle) {
    const std::int64_t block = cycle / 64;
    if (block % 16 == 15) return cycle % 64 < 20;
    return block % 2 == 1 && pattern() % 3 == 0;
  };
  CameraRtl rtl;
  EXPECT_EQ(rtl.run(pixels, gap, junk), 0);
}

TEST(ArtixCameraRtl, ResetDropsThePixelsInFlight) {
  CameraRtl rtl;
  const std::vector<Pixel> some = {{0, 0}, {639, 479}, {320, 240}, {17, 400}};
  rtl.reset_after(some, 3);
  // It works on after the reset.
  std::mt19937 junk(5);
  EXPECT_EQ(rtl.run({{1, 2}, {638, 0}, {320, 240}}, [](std::int64_t) { return false; }, junk), 0);
}

}  // namespace
}  // namespace tripsitter::rtl
