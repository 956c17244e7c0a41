// The artix cull's RTL (ts_artix_cull.sv) against artix::cull_bounds, bit for bit: random spheres anywhere in the
// formats, and spheres drawn to land where the method could go wrong (in view, just off screen, behind the camera
// and at the edge of that rule, across its plane, around it, and tiny ones on a pixel's ray), each taken back to
// back with junk on the ports while the block works. Each answer must come exactly Latency cycles after its start,
// within the 500 cycles the world's arrival leaves, with ready low in between.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rtl_ports.h"  // first: it includes verilated.h with its warnings silenced

#include <Vts_artix_cull.h>

#include <tripsitter/core/screen.h>
#include <tripsitter/core/sphere_kernel.h>
#include <tripsitter/device/artix_kernel.h>
#include <tripsitter/device/artix_units.h>

namespace tripsitter::rtl {
namespace {

namespace artix = device::artix;

constexpr int kLatency = 352;    // ts_artix_cull: 1 + 27 + 321 + 2 + 1
constexpr int kBound = 500;      // the cycles the world's arrival leaves (the brief's budget)
constexpr int kCoordBits = 22;   // ts_artix_pkg::CoordW: -2^21 <= c_k < 2^21
constexpr int kRadiusBits = 21;  // ts_artix_pkg::RadiusW: 1 <= r < 2^21
constexpr std::int64_t kCoordMax = (std::int64_t{1} << (kCoordBits - 1)) - 1;
constexpr std::int64_t kCoordMin = -(std::int64_t{1} << (kCoordBits - 1));
constexpr std::int64_t kRadiusMax = (std::int64_t{1} << kRadiusBits) - 1;

using Sphere = core::KernelSphere<std::int64_t>;

std::int64_t grown_of(std::int64_t r) { return r + (r >> 10) + 4; }

std::string describe(const Sphere& s) {
  std::ostringstream o;
  o << "c = (" << s.center.x << ", " << s.center.y << ", " << s.center.z << "), r = " << s.radius;
  return o.str();
}
std::string describe(const core::ScreenBounds& b) {
  std::ostringstream o;
  o << "cols " << b.col_lo << ".." << b.col_hi << ", rows " << b.row_lo << ".." << b.row_hi;
  return o.str();
}
bool same(const core::ScreenBounds& a, const core::ScreenBounds& b) {
  return a.col_lo == b.col_lo && a.col_hi == b.col_hi && a.row_lo == b.row_lo && a.row_hi == b.row_hi;
}

core::ScreenBounds model(const Sphere& s) {
  return artix::cull_bounds(artix::prepare_sphere(s, core::KernelSurface{}));
}

// One Verilated cull, clocked by hand: inputs set, settle with the clock low, rising edge.
class CullRtl {
 public:
  CullRtl() : junk_(99) {
    context_.randReset(2);  // random initial values: the reset must make them irrelevant
    top_ = std::make_unique<Vts_artix_cull>(&context_);
    top_->rst = 1;
    top_->start = 0;
    for (int i = 0; i < 3; ++i) tick();
    top_->rst = 0;
    tick();
  }

  // The bounds of `s`: start in the first cycle the block is ready, junk on the ports after it. Checks the cycle
  // contract; `cycles` is the start-to-done distance.
  core::ScreenBounds bounds(const Sphere& s, int& cycles) {
    for (int wait = 0; !top_->ready; ++wait) {
      if (wait > 2 * kBound) {
        ADD_FAILURE() << "the cull never became ready";
        return {};
      }
      tick();
    }
    top_->start = 1;
    put_sphere(s);
    tick();
    top_->start = 0;
    cycles = 1;
    while (!top_->done && cycles <= 2 * kBound) {
      if (top_->ready) ADD_FAILURE() << "ready while a sphere is in the works, cycle " << cycles << " after start";
      // Junk on the ports, and start pulses the block must ignore while busy.
      top_->start = junk_() % 4 == 0;
      put_sphere({{junk_coord(), junk_coord(), junk_coord()}, 1 + static_cast<std::int64_t>(junk_() % kRadiusMax)});
      tick();
      ++cycles;
    }
    top_->start = 0;
    if (!top_->done) {
      ADD_FAILURE() << "no done for " << describe(s);
      return {};
    }
    core::ScreenBounds b;
    if (!top_->empty)
      b = {static_cast<int>(top_->col_lo), static_cast<int>(top_->col_hi), static_cast<int>(top_->row_lo),
           static_cast<int>(top_->row_hi)};
    tick();
    EXPECT_EQ(top_->done, 0) << "done longer than a cycle";
    return b;
  }

 private:
  void put_sphere(const Sphere& s) {
    top_->cx = static_cast<IData>(s.center.x) & static_cast<IData>(mask(kCoordBits));
    top_->cy = static_cast<IData>(s.center.y) & static_cast<IData>(mask(kCoordBits));
    top_->cz = static_cast<IData>(s.center.z) & static_cast<IData>(mask(kCoordBits));
    top_->r = static_cast<IData>(s.radius);
  }
  std::int64_t junk_coord() {
    return kCoordMin + static_cast<std::int64_t>(junk_() % (std::uint64_t{1} << kCoordBits));
  }
  void tick() {
    rising_edge(*top_);
  }

  VerilatedContext context_;
  std::unique_ptr<Vts_artix_cull> top_;
  std::mt19937_64 junk_;
};

// Random spheres, each family aimed at a way the plane tests can go.
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : rng_(seed) {}
  std::uint64_t operator()() { return rng_(); }
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  // 1 .. max, log-uniform.
  std::int64_t log_uniform(std::int64_t max) {
    const double v = std::exp(uniform(0.0, std::log(static_cast<double>(max) + 1.0)));
    return std::clamp(static_cast<std::int64_t>(v), std::int64_t{1}, max);
  }
  std::int64_t coord(double v) { return std::clamp(static_cast<std::int64_t>(std::llround(v)), kCoordMin, kCoordMax); }
  std::int64_t any_coord() {
    if (rng_() % 16 == 0)
      return rng_() % 2 ? kCoordMax - static_cast<std::int64_t>(rng_() % 3)
                        : kCoordMin + static_cast<std::int64_t>(rng_() % 3);
    const std::int64_t m = rng_() % 8 == 0 ? static_cast<std::int64_t>(rng_() % 3) : log_uniform(kCoordMax);
    return rng_() % 2 ? m : -m;
  }
  std::int64_t radius() {
    return rng_() % 32 == 0 ? kRadiusMax - static_cast<std::int64_t>(rng_() % 3) : log_uniform(kRadiusMax);
  }

  Sphere anywhere() { return {{any_coord(), any_coord(), any_coord()}, radius()}; }
  // In front, the centre within (or just beyond) the field of view: x up to 1.2 z, y up to 0.9 z.
  Sphere in_view() {
    const double z = static_cast<double>(log_uniform(kCoordMax));
    const std::int64_t r =
        log_uniform(std::max<std::int64_t>(1, std::min<std::int64_t>(kRadiusMax, static_cast<std::int64_t>(z))));
    return {{coord(z * uniform(-1.2, 1.2)), coord(z * uniform(-0.9, 0.9)), coord(z)}, r};
  }
  // In front but beside the screen: the sphere's edge near the outermost column's or row's plane.
  Sphere off_screen() {
    const double z = static_cast<double>(log_uniform(kCoordMax / 2));
    const std::int64_t r =
        log_uniform(std::max<std::int64_t>(1, std::min<std::int64_t>(kRadiusMax, static_cast<std::int64_t>(z))));
    const double edge = rng_() % 2 ? 1.0 : 0.75;  // the side planes at |x| = z, the top and bottom at |y| = 0.75 z
    const double out = edge * z + static_cast<double>(r) * uniform(0.5, 2.0) * (rng_() % 2 ? 1 : -1);
    const double other = z * uniform(-1.5, 1.5);
    const double side = rng_() % 2 ? out : -out;
    return edge == 1.0 ? Sphere{{coord(side), coord(other), coord(z)}, r}
                       : Sphere{{coord(other), coord(side), coord(z)}, r};
  }
  // Behind the camera plane, mostly at the rule's edge: c_z + grown in -3..3.
  Sphere behind() {
    const std::int64_t r = radius();
    const std::int64_t cz = rng_() % 4 == 0 ? -static_cast<std::int64_t>(rng_() % static_cast<std::uint64_t>(kCoordMax))
                                            : -grown_of(r) + static_cast<std::int64_t>(rng_() % 7) - 3;
    return {{any_coord(), any_coord(), std::clamp(cz, kCoordMin, kCoordMax)}, r};
  }
  // Across the camera plane (|c_z| < grown) with the camera outside: the meeting planes wrap through z = 0.
  Sphere across() {
    const std::int64_t r = radius();
    const std::int64_t g = grown_of(r);
    const std::int64_t cz = static_cast<std::int64_t>(rng_() % static_cast<std::uint64_t>(2 * g - 1)) - (g - 1);
    const double d = static_cast<double>(r) * uniform(1.0, 4.0);  // the centre's distance across
    const double a = uniform(0.0, 6.283185307179586);
    return {{coord(d * std::cos(a)), coord(d * std::sin(a)), std::clamp(cz, kCoordMin, kCoordMax)}, r};
  }
  // Around the camera: |c| < r.
  Sphere around() {
    const std::int64_t r = radius();
    const double f = uniform(0.0, 0.57) * static_cast<double>(r);
    return {{coord(f * uniform(-1, 1)), coord(f * uniform(-1, 1)), coord(f * uniform(-1, 1))}, r};
  }
  // Tiny, on or next to the ray of a pixel.
  Sphere on_a_ray() {
    const int col = static_cast<int>(rng_() % core::kScreenWidth);
    const int row = static_cast<int>(rng_() % core::kScreenHeight);
    const double t = static_cast<double>(log_uniform(kCoordMax / 320));
    const double jitter = rng_() % 2 ? 0.0 : 1.0;
    return {{coord(t * (col - 320) + jitter * uniform(-3, 3)), coord(t * (row - 240) + jitter * uniform(-3, 3)),
             coord(t * 320)},
            1 + static_cast<std::int64_t>(rng_() % 8)};
  }

 private:
  std::mt19937_64 rng_;
};

// Whether some column or row inside the model's hull (before the margin) does not meet the sphere: the wrap case.
bool hull_has_a_gap(const Sphere& s) {
  const std::int64_t g = grown_of(s.radius);
  const std::int64_t r2 = g * g;
  for (int pencil = 0; pencil < 2; ++pencil) {
    const std::int64_t across = pencil == 0 ? s.center.x : s.center.y;
    const int count = pencil == 0 ? core::kScreenWidth : core::kScreenHeight;
    const auto range = core::meeting_range<core::Int128>(across, s.center.z, r2, std::int64_t{320}, count, count / 2);
    for (int i = range[0]; i <= range[1]; ++i)
      if (!core::plane_meets<core::Int128>(across, s.center.z, r2, std::int64_t{320}, std::int64_t{i - count / 2}))
        return true;
  }
  return false;
}

struct Tally {
  int spheres = 0, empty = 0, partial = 0, whole = 0, gaps = 0, behind_edge = 0;
  int narrow = 0;  // at most 5 columns and 5 rows
};

// Runs `n` spheres of a family through the RTL; returns how many differ from the model, and tallies the outcomes.
template <class Family>
int run_family(CullRtl& rtl, int n, const Family& family, Tally& tally) {
  int bad = 0;
  for (int i = 0; i < n; ++i) {
    const Sphere s = family();
    int cycles = 0;
    const core::ScreenBounds got = rtl.bounds(s, cycles);
    const core::ScreenBounds want = model(s);
    EXPECT_EQ(cycles, kLatency) << describe(s);
    EXPECT_LE(cycles, kBound);
    if (!same(got, want)) {
      if (++bad <= 10) ADD_FAILURE() << describe(s) << ": RTL " << describe(got) << ", model " << describe(want);
    }
    ++tally.spheres;
    const bool empty = want.col_lo > want.col_hi;
    tally.empty += empty;
    tally.whole += !empty && want.col_lo == 0 && want.col_hi == 639 && want.row_lo == 0 && want.row_hi == 479;
    tally.partial += !empty && !(want.col_lo == 0 && want.col_hi == 639 && want.row_lo == 0 && want.row_hi == 479);
    tally.narrow += !empty && want.col_hi - want.col_lo < 5 && want.row_hi - want.row_lo < 5;
    const std::int64_t front = s.center.z + grown_of(s.radius);
    tally.behind_edge += front >= 0 && front <= 1;
    if (!empty && hull_has_a_gap(s)) ++tally.gaps;
  }
  return bad;
}

TEST(ArtixCullRtl, RandomSpheresAnywhereEqualTheModel) {
  CullRtl rtl;
  Draw draw(1);
  Tally t;
  EXPECT_EQ(run_family(
                rtl, 20000, [&] { return draw.anywhere(); }, t),
            0);
  // The draw reaches both outcomes.
  EXPECT_GT(t.empty, 4000);
  EXPECT_GT(t.partial, 1000);
  EXPECT_GT(t.whole, 1000);
  EXPECT_GT(t.gaps, 100);
}

TEST(ArtixCullRtl, SpheresInViewAndOffScreenEqualTheModel) {
  CullRtl rtl;
  Draw draw(2);
  Tally t;
  EXPECT_EQ(run_family(
                rtl, 3000, [&] { return draw.in_view(); }, t),
            0);
  EXPECT_EQ(run_family(
                rtl, 3000, [&] { return draw.off_screen(); }, t),
            0);
  EXPECT_GT(t.partial, 2500);
  EXPECT_GT(t.empty, 300);
}

TEST(ArtixCullRtl, SpheresBehindTheCameraEqualTheModel) {
  CullRtl rtl;
  Draw draw(3);
  Tally t;
  EXPECT_EQ(run_family(
                rtl, 2000, [&] { return draw.behind(); }, t),
            0);
  // Both sides of c_z + grown <= 0, at the edge itself.
  EXPECT_GT(t.behind_edge, 300);
  EXPECT_GT(t.empty, 800);
  EXPECT_GT(t.spheres - t.empty, 200);
}

TEST(ArtixCullRtl, SpheresAcrossAndAroundTheCameraEqualTheModel) {
  CullRtl rtl;
  Draw draw(4);
  Tally t;
  EXPECT_EQ(run_family(
                rtl, 3000, [&] { return draw.across(); }, t),
            0);
  EXPECT_EQ(run_family(
                rtl, 1000, [&] { return draw.around(); }, t),
            0);
  // The wrap case: hulls holding planes that miss the sphere.
  EXPECT_GT(t.gaps, 100);
  EXPECT_GT(t.whole, 1000);
}

TEST(ArtixCullRtl, TinySpheresOnAPixelsRayEqualTheModel) {
  CullRtl rtl;
  Draw draw(5);
  Tally t;
  EXPECT_EQ(run_family(
                rtl, 4000, [&] { return draw.on_a_ray(); }, t),
            0);
  EXPECT_GT(t.narrow, 3000);
}

// The corners of the formats, and a sphere whose hull is a single column and row at each edge of the screen.
TEST(ArtixCullRtl, ExtremesEqualTheModel) {
  CullRtl rtl;
  std::vector<Sphere> spheres;
  for (const std::int64_t x : {kCoordMin, kCoordMax, std::int64_t{0}})
    for (const std::int64_t y : {kCoordMin, kCoordMax, std::int64_t{0}})
      for (const std::int64_t z : {kCoordMin, kCoordMax, std::int64_t{0}, std::int64_t{-4}, std::int64_t{-5}})
        for (const std::int64_t r : {std::int64_t{1}, kRadiusMax}) spheres.push_back({{x, y, z}, r});
  for (const int col : {0, 1, 319, 320, 638, 639})
    for (const int row : {0, 1, 239, 240, 478, 479})
      spheres.push_back({{6000 * (col - 320), 6000 * (row - 240), 6000 * 320}, 1});
  int bad = 0;
  for (const Sphere& s : spheres) {
    int cycles = 0;
    const core::ScreenBounds got = rtl.bounds(s, cycles);
    const core::ScreenBounds want = model(s);
    EXPECT_EQ(cycles, kLatency);
    if (!same(got, want) && ++bad <= 10)
      ADD_FAILURE() << describe(s) << ": RTL " << describe(got) << ", model " << describe(want);
  }
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace tripsitter::rtl
